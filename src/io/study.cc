#include <base/input_error.h>
#include <base/text.h>
#include <io/body_scene.h>
#include <io/study.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <random>
#include <sstream>

namespace flextrack::io
{
using dealii::ParameterHandler;
using dealii::Patterns::Anything;
namespace fs = std::filesystem;

namespace
{
constexpr unsigned int max_cases = 100000;
const char *const statistics[] = {"max", "min", "max_abs", "final", "mean", "time_of_max", "time_of_min"};

/// @p text split at @p separator outside parentheses (so "min(a, b)" stays one item), trimmed;
/// empty items dropped.
std::vector<std::string> split_outside_parentheses(const std::string &text, const char separator)
{
  std::vector<std::string> items;
  std::string item;
  int depth = 0;
  for (const char c : text)
    {
      if (c == '(') ++depth;
      if (c == ')' && depth > 0) --depth;
      if (c == separator && depth == 0)
        {
          if (!base::trim(item).empty()) items.push_back(base::trim(item));
          item.clear();
        }
      else
        item += c;
    }
  if (!base::trim(item).empty()) items.push_back(base::trim(item));
  return items;
}

/// A number as the text a case sets: 12 significant digits, so that 0.1 + 2 * 0.1 is "0.3".
std::string value_text(const double x)
{
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.12g", x);
  return buffer;
}

/// The values of a 'Values' entry: items separated by ';' if there is one, else by ',' (outside
/// parentheses); an item FROM:STEP:TO is the range FROM, FROM + STEP, ... up to TO.
std::vector<std::string> parse_values(const std::string &text, const std::string &entry)
{
  std::vector<std::string> values;
  for (const auto &item : split_outside_parentheses(text, text.find(';') != std::string::npos ? ';' : ','))
    {
      const auto parts = base::split(item, ':');
      if (parts.size() != 3 || item.find('(') != std::string::npos)
        {
          values.push_back(item);
          continue;
        }
      const double from = base::parse_number(parts[0], entry, "the start of the range " + item);
      const double step = base::parse_number(parts[1], entry, "the step of the range " + item);
      const double to = base::parse_number(parts[2], entry, "the end of the range " + item);
      if (step == 0 || (to - from) / step < 0)
        throw InputError(entry, "the range '" + item + "' (FROM:STEP:TO) never reaches its end: the step must be "
                                "nonzero and point from FROM to TO");
      const double n = std::floor((to - from) / step * (1 + 1e-12) + 1e-9);
      if (n >= max_cases)
        throw InputError(entry, "the range '" + item + "' has more than " + std::to_string(max_cases) + " values");
      // FROM + k STEP in floating point: 0.3 - 3 x 0.1 is -5.6e-17, not 0 (an entry that must not
      // be negative would refuse it), and the last value may miss TO by as much.
      const double scale = std::max({std::abs(from), std::abs(to), std::abs(step)});
      for (unsigned int k = 0; k <= n; ++k)
        {
          double x = from + k * step;
          if (std::abs(x - to) <= 1e-9 * std::abs(step)) x = to;
          if (std::abs(x) <= 1e-12 * scale) x = 0;
          values.push_back(value_text(x));
        }
    }
  if (values.empty()) throw InputError(entry, "gives no value; e.g. 'Values = 4, 8, 16' or 'Values = 0.5:0.25:1.5'");
  return values;
}

Quantity parse_quantity(const std::string &text, const std::string &entry)
{
  Quantity q;
  q.text = text;
  const auto open = text.find('(');
  if (open == std::string::npos)
    {
      for (const char c : text)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/' || c == ' ' || c == '-' || c == '.'))
          throw InputError(entry, "'" + base::printable_excerpt(text) + "' is neither a path of summary.json (e.g. "
                                  "'integrator/steps') nor STATISTIC(COLUMN) (e.g. 'max(head_deviation_m)')");
      q.kind = Quantity::Kind::summary;
      q.path = text;
      return q;
    }
  const std::string name = base::trim(text.substr(0, open));
  if (text.back() != ')')
    throw InputError(entry, "'" + base::printable_excerpt(text) + "' does not end in ')'");
  q.path = base::trim(text.substr(open + 1, text.size() - open - 2));
  if (q.path.empty() || q.path.find_first_of("(),") != std::string::npos)
    throw InputError(entry, "'" + base::printable_excerpt(text) + "' needs one column or probe name in its parentheses");
  if (name == "difference")
    {
      q.kind = Quantity::Kind::reference;
      return q;
    }
  if (std::find(std::begin(statistics), std::end(statistics), name) == std::end(statistics))
    throw InputError(entry, "'" + base::printable_excerpt(name) + "' in '" + base::printable_excerpt(text) +
                              "' is no statistic; allowed: max, min, max_abs, final, mean, time_of_max, time_of_min, "
                              "and difference(PROBE)");
  q.kind = Quantity::Kind::column;
  q.statistic = name;
  return q;
}

/// Numbers 0 <= u < 1 from a generator the C++ standard defines exactly (mt19937_64), so a
/// sample is the same on every machine and compiler.
class UnitSample
{
public:
  explicit UnitSample(const unsigned int seed) : generator(seed) {}
  double next() { return static_cast<double>(generator() >> 11) * 0x1.0p-53; }
  unsigned int below(const unsigned int n) { return static_cast<unsigned int>(next() * n); }

private:
  std::mt19937_64 generator;
};
} // namespace

void declare_study_parameter_list(ParameterHandler &prm)
{
  prm.enter_subsection("Study");
  prm.declare_entry("Parameters", "", Anything(),
                    "Names of the varied parameters, separated by commas (letters, digits, '_'); each parameter "
                    "NAME is described in 'subsection Parameter NAME' and is a column of sweep.csv [-].");
  prm.leave_subsection();
}

void declare_study(ParameterHandler &prm, const std::vector<std::string> &names)
{
  declare_model_entry(prm);
  declare_study_parameter_list(prm);
  prm.enter_subsection("Study");
  prm.declare_entry("Scene", "", dealii::Patterns::FileName(),
                    "The multibody scene every case runs (relative to the study file's folder) [-].");
  prm.declare_entry("Design", "grid", dealii::Patterns::Selection("grid|zip|random|latin hypercube"),
                    "How the parameters' values make cases: 'grid' (every combination, the first parameter "
                    "varying slowest), 'zip' (the k-th values of every parameter together; lists of equal "
                    "length), 'random' (Samples points drawn uniformly from each parameter's Interval) or "
                    "'latin hypercube' (Samples points, one in each of Samples equal slices of every Interval) [-].");
  prm.declare_entry("Samples", "0", dealii::Patterns::Integer(0, max_cases),
                    "Number of cases of a random or Latin-hypercube design [-].");
  prm.declare_entry("Seed", "1", dealii::Patterns::Integer(0),
                    "Seed of a random or Latin-hypercube design (mt19937_64: the same sample on every machine) [-].");
  prm.declare_entry("Set", "", Anything(),
                    "Entries set in every case, as --set takes them, separated by ';': e.g. 'Multibody/End "
                    "time=2; Output/Animation interval=0; Body I:Reduction/Track stations=8' [-]. Cases draw no run.png "
                    "unless this sets 'Output/Plots=true'.");
  prm.declare_entry("Collect", "", Anything(),
                    "Quantities collected from every case into sweep.csv, separated by commas: a path of the "
                    "case's summary.json ('integrator/steps', 'rigid_reference/largest_deviation/0/max_deviation_m'); "
                    "STATISTIC(COLUMN) of a column of probes.csv, deviation.csv or monitors.csv, STATISTIC one of "
                    "max, min, max_abs, final, mean, time_of_max, time_of_min ('max(head_deviation_m)'); "
                    "difference(PROBE): the probe's largest distance over the output times from its position in "
                    "the Reference case [units of the column or summary entry].");
  prm.declare_entry("Reference case", "none", Anything(),
                    "The case that 'difference(PROBE)' compares with: its number (1 = the first case of the "
                    "design), 'last', or 'none' [-].");
  prm.declare_entry("Output directory", "", Anything(),
                    "Folder of sweep.csv, sweep.png and the case folders case_NNNN/ (empty: output/<study file "
                    "name without extension>; -o overrides it) [-].");
  prm.leave_subsection();
  for (const auto &name : names)
    {
      prm.enter_subsection("Parameter " + name);
      prm.declare_entry("Entry", "", Anything(),
                        "The entry this parameter sets, as --set names it: 'Joint slide/Driver', 'Multibody/End "
                        "time', or 'Body NAME:PATH' for an entry of flexible body NAME's body scene [-].");
      prm.declare_entry("Values", "", Anything(),
                        "Grid and zip designs: the values, separated by commas (by ';' if a value holds commas); "
                        "FROM:STEP:TO is a range ('0.5:0.25:1.5' = 0.5, 0.75, 1, 1.25, 1.5) [unit of the entry].");
      prm.declare_entry("Interval", "", Anything(),
                        "Random and Latin-hypercube designs: 'LOWER, UPPER', the interval sampled [unit of the entry].");
      prm.declare_entry("Integer", "false", dealii::Patterns::Bool(),
                        "Random and Latin-hypercube designs: round each sampled value to an integer [-].");
      prm.declare_entry("Template", "{}", Anything(),
                        "The value set in a case, with {} replaced by the parameter's value: e.g. "
                        "'0.4 + 0.8*((1 - cos({}*t))/2)^2' varies the frequency of a driver [-].");
      prm.leave_subsection();
    }
}

Study read_study(const SceneFile &file)
{
  try
    {
      if (file.model != "study")
        throw InputError("Model", "is '" + file.model + "'; 'flextrack sweep' needs a study file ('Model = study', doc/sweep.md)");
      file.lists->enter_subsection("Study");
      const std::string list = file.lists->get("Parameters");
      file.lists->leave_subsection();
      const auto names = base::parse_name_list(list, "Study/Parameters", "parameter name");
      ParameterHandler prm;
      declare_study(prm, names);
      file.parse(prm, false);
      Study study;
      study.file = file.name;
      prm.enter_subsection("Study");
      const std::string scene = base::trim(prm.get("Scene"));
      if (scene.empty()) throw InputError("Study/Scene", "names no scene; give the multibody scene every case runs");
      study.scene = fs::absolute(fs::path(scene).is_absolute() ? fs::path(scene) : fs::path(file.directory) / scene).lexically_normal().string();
      study.design = prm.get("Design");
      study.samples = prm.get_integer("Samples");
      study.seed = prm.get_integer("Seed");
      // A case draws no run.png unless the study's Set asks for it (sweep.png is the study's
      // picture; gnuplot costs about 0.1 s a case). Set after it, a user's entry wins.
      study.fixed.push_back(parse_override("Output/Plots=false"));
      for (const auto &item : base::split(prm.get("Set"), ';'))
        {
          try
            {
              study.fixed.push_back(parse_override(item));
            }
          catch (const InputError &e)
            {
              throw InputError("Study/Set", e.message());
            }
        }
      for (const auto &item : split_outside_parentheses(prm.get("Collect"), ','))
        study.quantities.push_back(parse_quantity(item, "Study/Collect"));
      const std::string reference = base::trim(prm.get("Reference case"));
      study.output_directory = base::trim(prm.get("Output directory"));
      prm.leave_subsection();
      if (names.empty()) throw InputError("Study/Parameters", "names no parameter; a study varies at least one entry");
      for (const auto &name : names)
        {
          const std::string prefix = "Parameter " + name + "/";
          if (!file.has_subsection("Parameter " + name))
            throw InputError("Study/Parameters", "lists '" + name + "' but there is no 'subsection Parameter " + name + "'");
          prm.enter_subsection("Parameter " + name);
          StudyParameter p;
          p.name = name;
          const std::string entry = base::trim(prm.get("Entry"));
          if (entry.empty()) throw InputError(prefix + "Entry", "names no entry; e.g. 'Multibody/End time'");
          try
            {
              p.entry = parse_override(entry + "=0");
            }
          catch (const InputError &e)
            {
              throw InputError(prefix + "Entry", e.message());
            }
          p.value_template = base::trim(prm.get("Template"));
          if (p.value_template.find("{}") == std::string::npos)
            throw InputError(prefix + "Template", "'" + base::printable_excerpt(p.value_template) + "' has no {} for the value");
          p.integer = prm.get_bool("Integer");
          const bool sampled = study.design == "random" || study.design == "latin hypercube";
          const std::string values = base::trim(prm.get("Values")), interval = base::trim(prm.get("Interval"));
          if (sampled)
            {
              if (!values.empty()) throw InputError(prefix + "Values", "a " + study.design + " design samples an Interval; give 'Interval = LOWER, UPPER' instead");
              const auto bounds = base::split(interval, ',');
              if (bounds.size() != 2) throw InputError(prefix + "Interval", "needs 'LOWER, UPPER', two numbers");
              p.lower = base::parse_number(bounds[0], prefix + "Interval", "the lower bound");
              p.upper = base::parse_number(bounds[1], prefix + "Interval", "the upper bound");
              if (!(p.lower < p.upper)) throw InputError(prefix + "Interval", "needs LOWER < UPPER");
            }
          else
            {
              if (!interval.empty()) throw InputError(prefix + "Interval", "is for random and Latin-hypercube designs; a " + study.design + " design takes 'Values'");
              p.values = parse_values(values, prefix + "Values");
            }
          prm.leave_subsection();
          study.parameters.push_back(std::move(p));
        }
      const bool sampled = study.design == "random" || study.design == "latin hypercube";
      if (sampled && study.samples == 0) throw InputError("Study/Samples", "is 0; a " + study.design + " design needs the number of cases");
      if (!sampled && study.samples != 0) throw InputError("Study/Samples", "is for random and Latin-hypercube designs; a " + study.design + " design has as many cases as its values give");
      double n_cases = sampled ? study.samples : 1;
      if (study.design == "grid")
        for (const auto &p : study.parameters) n_cases *= p.values.size();
      if (study.design == "zip")
        {
          n_cases = study.parameters.front().values.size();
          for (const auto &p : study.parameters)
            if (p.values.size() != n_cases)
              throw InputError("Parameter " + p.name + "/Values", "has " + std::to_string(p.values.size()) + " values, '" +
                                 study.parameters.front().name + "' has " + base::number_text(n_cases) + "; a zip design takes the k-th value of each");
        }
      if (n_cases > max_cases)
        throw InputError("Study/Design", "makes " + base::number_text(n_cases) + " cases; at most " + std::to_string(max_cases));
      if (reference == "last")
        study.reference_case = static_cast<unsigned int>(n_cases);
      else if (reference != "none")
        {
          const double r = base::parse_number(reference, "Study/Reference case", "a case number, 'last' or 'none'");
          if (r != std::floor(r) || r < 1 || r > n_cases)
            throw InputError("Study/Reference case", "is " + reference + "; allowed: 1 to " + base::number_text(n_cases) + ", 'last' or 'none'");
          study.reference_case = static_cast<unsigned int>(r);
        }
      for (const auto &q : study.quantities)
        if (q.kind == Quantity::Kind::reference && study.reference_case == 0)
          throw InputError("Study/Collect", "'" + q.text + "' compares with the Reference case, which is 'none'; set "
                                            "'Reference case' to a case number or 'last'");
      return study;
    }
  catch (const InputError &e)
    {
      throw e.file().empty() ? e.in_file(file.name) : e;
    }
}

std::vector<StudyCase> Study::cases(const std::string &scene_text, const std::string &output_folder) const
{
  // The values of each case, one per parameter.
  std::vector<std::vector<std::string>> rows;
  if (design == "grid")
    {
      rows.emplace_back();
      for (const auto &p : parameters)
        {
          std::vector<std::vector<std::string>> longer;
          for (const auto &row : rows)
            for (const auto &v : p.values)
              {
                longer.push_back(row);
                longer.back().push_back(v);
              }
          rows = std::move(longer);
        }
    }
  else if (design == "zip")
    for (std::size_t k = 0; k < parameters.front().values.size(); ++k)
      {
        rows.emplace_back();
        for (const auto &p : parameters) rows.back().push_back(p.values[k]);
      }
  else
    {
      UnitSample u(seed);
      rows.assign(samples, std::vector<std::string>(parameters.size()));
      for (std::size_t j = 0; j < parameters.size(); ++j)
        {
          const auto &p = parameters[j];
          // Latin hypercube: sample i falls into slice slot[i] of the interval, each slice once.
          std::vector<unsigned int> slot(samples);
          for (unsigned int i = 0; i < samples; ++i) slot[i] = i;
          if (design == "latin hypercube")
            for (unsigned int i = samples; i > 1; --i) std::swap(slot[i - 1], slot[u.below(i)]);
          for (unsigned int i = 0; i < samples; ++i)
            {
              const double fraction = design == "random" ? u.next() : (slot[i] + u.next()) / samples;
              double x = p.lower + fraction * (p.upper - p.lower);
              if (p.integer) x = std::round(x);
              rows[i][j] = value_text(x);
            }
        }
    }
  const unsigned int width = std::max<std::size_t>(4, std::to_string(rows.size()).size());
  std::vector<StudyCase> result;
  for (std::size_t i = 0; i < rows.size(); ++i)
    {
      StudyCase c;
      c.number = static_cast<unsigned int>(i + 1);
      c.values = rows[i];
      c.set = fixed;
      std::uint64_t h = fnv1a(std::string("flextrack study case v1 ") + FLEXTRACK_VERSION + "\n" + scene_text);
      for (std::size_t j = 0; j < parameters.size(); ++j)
        {
          ParameterOverride o = parameters[j].entry;
          o.value = parameters[j].value_template;
          for (std::size_t at = 0; (at = o.value.find("{}", at)) != std::string::npos; at += rows[i][j].size())
            o.value.replace(at, 2, rows[i][j]);
          c.set.push_back(o);
        }
      for (const auto &o : c.set) h = fnv1a("\n" + o.text(), h);
      std::ostringstream hex, number;
      hex << std::hex << std::setw(16) << std::setfill('0') << h;
      number << std::setw(width) << std::setfill('0') << c.number;
      c.key = hex.str();
      c.folder = output_folder + "/case_" + number.str();
      result.push_back(std::move(c));
    }
  return result;
}

namespace
{
/// A CSV file of a header and numeric rows (FlexTrack's own result files).
struct NumericTable
{
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  bool read(const std::string &file)
  {
    std::ifstream in(file);
    std::string line;
    if (!in || !std::getline(in, line)) return false;
    columns = base::split(line, ',');
    while (std::getline(in, line))
      {
        std::vector<double> row;
        std::istringstream cells(line);
        for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::strtod(cell.c_str(), nullptr));
        if (row.size() == columns.size()) rows.push_back(std::move(row));
      }
    return true;
  }
  int column(const std::string &name) const
  {
    const auto at = std::find(columns.begin(), columns.end(), name);
    return at == columns.end() ? -1 : static_cast<int>(at - columns.begin());
  }
};

std::string statistic_of(const NumericTable &table, const int column, const std::string &statistic)
{
  if (table.rows.empty()) return "";
  const auto value = [&](const std::size_t r) { return table.rows[r][column]; };
  std::size_t arg_max = 0, arg_min = 0;
  double sum = 0, largest_abs = 0;
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    {
      if (value(r) > value(arg_max)) arg_max = r;
      if (value(r) < value(arg_min)) arg_min = r;
      sum += value(r);
      largest_abs = std::max(largest_abs, std::abs(value(r)));
    }
  double x = 0;
  if (statistic == "max") x = value(arg_max);
  else if (statistic == "min") x = value(arg_min);
  else if (statistic == "max_abs") x = largest_abs;
  else if (statistic == "final") x = value(table.rows.size() - 1);
  else if (statistic == "mean") x = sum / table.rows.size();
  else if (statistic == "time_of_max") x = table.rows[arg_max][0];
  else if (statistic == "time_of_min") x = table.rows[arg_min][0];
  return value_text(x);
}

/// The value at '/'-separated @p path of a JSON tree (array elements by their index), "" if absent
/// or not a single value.
std::string summary_value(const boost::property_tree::ptree &tree, const std::string &path)
{
  const boost::property_tree::ptree *node = &tree;
  for (const auto &key : base::split(path, '/'))
    {
      const auto found = node->find(key);
      if (found != node->not_found())
        {
          node = &found->second;
          continue;
        }
      // An array's elements have empty keys: take the index-th.
      char *end = nullptr;
      const unsigned long index = std::strtoul(key.c_str(), &end, 10);
      if (*end != '\0' || index >= node->size()) return "";
      auto child = node->begin();
      std::advance(child, index);
      if (!child->first.empty()) return "";
      node = &child->second;
    }
  if (!node->empty()) return "";
  // Numbers with the 12 digits of the other columns (summary.json prints 17).
  const std::string &text = node->data();
  char *end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && std::isfinite(x) ? value_text(x) : text;
}
} // namespace

std::vector<std::string> collect_quantities(const std::vector<Quantity> &quantities, const std::string &folder)
{
  boost::property_tree::ptree summary;
  bool have_summary = false;
  try
    {
      if (fs::exists(folder + "/summary.json"))
        {
          boost::property_tree::read_json(folder + "/summary.json", summary);
          have_summary = true;
        }
    }
  catch (const boost::property_tree::json_parser_error &)
    {}
  std::map<std::string, NumericTable> tables; // read when a quantity first needs them
  const auto table = [&](const std::string &name) -> const NumericTable & {
    if (tables.find(name) == tables.end()) tables[name].read(folder + "/" + name);
    return tables[name];
  };
  std::vector<std::string> values;
  for (const auto &q : quantities)
    {
      std::string value;
      if (q.kind == Quantity::Kind::summary && have_summary)
        value = summary_value(summary, q.path);
      else if (q.kind == Quantity::Kind::column)
        for (const char *name : {"probes.csv", "deviation.csv", "monitors.csv"})
          if (const int c = table(name).column(q.path); c >= 0)
            {
              value = statistic_of(table(name), c, q.statistic);
              break;
            }
      values.push_back(value);
    }
  return values;
}

std::string probe_difference(const std::string &probe, const std::string &folder, const std::string &reference_folder)
{
  NumericTable run, reference;
  if (!run.read(folder + "/probes.csv") || !reference.read(reference_folder + "/probes.csv")) return "";
  if (run.rows.size() != reference.rows.size() || run.rows.empty()) return "";
  int columns[2][3];
  for (int k = 0; k < 3; ++k)
    {
      const std::string name = probe + "_" + "xyz"[k] + "_m";
      columns[0][k] = run.column(name);
      columns[1][k] = reference.column(name);
      if (columns[0][k] < 0 || columns[1][k] < 0) return "";
    }
  double largest = 0;
  for (std::size_t r = 0; r < run.rows.size(); ++r)
    {
      const double t = run.rows[r][0], t_reference = reference.rows[r][0];
      if (std::abs(t - t_reference) > 1e-9 * std::max(1.0, std::abs(t))) return "";
      double d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += std::pow(run.rows[r][columns[0][k]] - reference.rows[r][columns[1][k]], 2);
      largest = std::max(largest, std::sqrt(d2));
    }
  return value_text(largest);
}
} // namespace flextrack::io
