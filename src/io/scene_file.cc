#include <base/input_error.h>
#include <base/parse_error.h>
#include <base/text.h>
#include <fem/body.h>
#include <fem/load_case.h>
#include <io/scene_file.h>
#include <io/study.h>
#include <multibody/simulation_settings.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

namespace flextrack::io
{
using dealii::ParameterHandler;
namespace fs = std::filesystem;

namespace
{
constexpr std::uintmax_t max_text_bytes = 16u << 20;
constexpr unsigned int max_include_depth = 8;
constexpr unsigned int max_json_depth = 64;

/// Pass 1 of every scene: the "Model" entry and the lists of names. One row per list, declared
/// by the class that owns it.
void declare_first_pass(ParameterHandler &prm)
{
  declare_model_entry(prm);
  fem::Body::declare_arm_list(prm); // Body/Arms
  fem::StaticSettings::declare_load_case_list(prm); // Static/Load cases
  multibody::SceneNames::declare_name_lists(prm); // Multibody/Bodies, Joints, Forces, Probes
  declare_study_parameter_list(prm);                // Study/Parameters
}

std::string read_bytes(const std::string &file, const std::string &what)
{
  std::error_code ec;
  if (fs::is_directory(file, ec))
    throw InputError("", "is a folder, not a " + what + "; give a file", file);
  if (!fs::exists(file, ec)) throw InputError("", "cannot open the " + what + ": no such file", file);
  if (!fs::is_regular_file(file, ec))
    throw InputError("", "is not a regular file (a device or a pipe?); give a " + what, file);
  if (fs::file_size(file, ec) > max_text_bytes)
    throw InputError("", "is larger than 16 MiB; a " + what + " is a short text", file);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError("", "cannot open the " + what + " (permissions?)", file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The text with every "include FILE" line replaced by that file's text (recursively, at most
/// max_include_depth deep), so that a file including itself is refused instead of recursing.
std::string expand_includes(const std::string &text, const std::string &name, const std::string &directory,
                            const unsigned int depth)
{
  std::istringstream lines(text);
  std::ostringstream out;
  for (std::string line; std::getline(lines, line);)
    {
      const std::string t = base::trim(line);
      if (t.rfind("include ", 0) != 0 && t.rfind("include\t", 0) != 0)
        {
          out << line << "\n";
          continue;
        }
      if (depth >= max_include_depth)
        throw InputError("include", "includes are nested more than " + std::to_string(max_include_depth) +
                                      " deep (does a file include itself?)", name);
      const fs::path target = fs::path(directory) / base::trim(t.substr(8));
      const auto parent = target.parent_path().string();
      out << expand_includes(read_bytes(target.string(), "included parameter file"), target.string(),
                             parent.empty() ? "." : parent, depth + 1);
    }
  return out.str();
}

/// A whole value that is one subnormal number (4.9e-324, 1e-320: nonzero, below 2.2e-308 in
/// magnitude). deal.II's Patterns::Double accepts it, but ParameterHandler::get_double cannot
/// convert it and throws, which the command line could only report as an internal error.
bool is_subnormal_number(const std::string &value)
{
  if (value.empty()) return false;
  char *end = nullptr;
  errno = 0;
  const double d = std::strtod(value.c_str(), &end);
  if (end != value.c_str() + value.size()) return false;
  return std::fpclassify(d) == FP_SUBNORMAL || (d == 0 && errno == ERANGE);
}

/// Refuses, naming the entry, a subnormal number as the value of any entry of @p prm (found by
/// the fuzz driver, tests/fuzz: 'set Relative tolerance = 4.9e-324' ended in an internal error).
void refuse_subnormal_numbers(const ParameterHandler &prm, const std::string &file)
{
  std::ostringstream printed;
  prm.print_parameters(printed, ParameterHandler::ShortPRM);
  std::istringstream lines(printed.str());
  std::vector<std::string> path;
  for (std::string line; std::getline(lines, line);)
    {
      const std::string t = base::trim(line);
      if (t.rfind("subsection ", 0) == 0) path.push_back(t.substr(11));
      else if (t == "end" && !path.empty()) path.pop_back();
      else if (const auto eq = t.find(" = "); t.rfind("set ", 0) == 0 && eq != std::string::npos)
        if (const std::string value = base::trim(t.substr(eq + 3)); is_subnormal_number(value))
          {
            std::string entry;
            for (const auto &p : path) entry += p + "/";
            throw InputError(entry + base::trim(t.substr(4, eq - 4)), // names are padded for alignment
                             "'" + value + "' is a subnormal number (nonzero, below 2.2e-308 in magnitude); "
                             "write 0 or a number of normal size",
                             file);
          }
    }
}

/// Deepest nesting of braces and brackets outside strings.
unsigned int json_depth(const std::string &text)
{
  unsigned int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text)
    {
      if (in_string)
        {
          if (escaped) escaped = false;
          else if (c == '\\') escaped = true;
          else if (c == '"') in_string = false;
          continue;
        }
      if (c == '"') in_string = true;
      else if (c == '{' || c == '[') deepest = std::max(deepest, ++depth);
      else if ((c == '}' || c == ']') && depth > 0) --depth;
    }
  return deepest;
}
} // namespace

void declare_model_entry(ParameterHandler &prm)
{
  prm.declare_entry("Model", "arm", dealii::Patterns::Selection("arm|solid|body|multibody|study"),
                    "The structure of the scene: 'arm' (a curved beam, subsection Arm), 'solid' (a 3D body "
                    "meshed with hexahedra, subsection Solid) or 'body' (a flexible body of a solid part and "
                    "named arms, subsection Body, reduced by 'flextrack reduce') or 'multibody' (bodies, joints, forces "
                    "and probes, subsection Multibody, simulated by 'flextrack run'; doc/multibody.md) or 'study' (a "
                    "parameter study of a multibody scene, subsection Study, run by 'flextrack sweep'; doc/sweep.md).");
}

namespace
{
bool is_lower_hex(const char c)
{
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
}

/// @p text with every '_' of a JSON key that does not start a mangled character ("_" and two
/// lower-case hex digits, as deal.II writes them) written as "_5f". deal.II demangles every key
/// it reads, also of the subsections pass 1 skips, and its debug library stops at an assertion on
/// a plain "my_bob" (the release library reads a garbled name). Keys named exactly by
/// with_mangled_json_keys are already in that form.
std::string with_demanglable_keys(const std::string &text)
{
  std::string out;
  out.reserve(text.size());
  std::size_t i = 0;
  while (i < text.size())
    {
      if (text[i] != '"')
        {
          out += text[i++];
          continue;
        }
      std::size_t end = i + 1; // the closing quote
      while (end < text.size() && text[end] != '"') end += text[end] == '\\' ? 2 : 1;
      if (end >= text.size())
        {
          out += text.substr(i);
          break;
        }
      std::size_t next = end + 1;
      while (next < text.size() && std::isspace(static_cast<unsigned char>(text[next]))) ++next;
      const bool key = next < text.size() && text[next] == ':';
      for (std::size_t k = i; k <= end; ++k)
        {
          const bool mangled = k + 2 < end && is_lower_hex(text[k + 1]) && is_lower_hex(text[k + 2]);
          out += key && text[k] == '_' && !mangled ? std::string("_5f") : std::string(1, text[k]);
        }
      i = end + 1;
    }
  return out;
}
} // namespace

namespace
{
/// The subsections open at line @p line (1-based) of a .prm text, outermost first.
std::vector<std::string> subsections_at(const std::string &text, const unsigned int line)
{
  std::vector<std::string> open;
  std::istringstream lines(text);
  std::string l;
  for (unsigned int n = 1; n < line && std::getline(lines, l); ++n)
    {
      l = base::trim(l.substr(0, l.find('#')));
      if (l.rfind("subsection ", 0) == 0)
        open.push_back(base::trim(l.substr(11)));
      else if (l == "end" && !open.empty())
        open.pop_back();
    }
  return open;
}

/// deal.II's message for a misspelt name or value, said with the subsection it is in, the nearest
/// declared names and the allowed values (issue 25, item 6: deal.II names neither the subsection
/// nor the name meant, and prints a selection as its raw pattern). Other messages are returned
/// as they are.
std::string explained_parse_error(const std::string &message, const std::string &text, const ParameterHandler &prm)
{
  std::smatch m;
  if (!std::regex_search(message, m, std::regex(R"(Line <(\d+)>)"))) return message;
  const unsigned int line = std::stoul(m[1]);
  const std::vector<std::string> open = subsections_at(text, line);
  const std::string path = base::joined(open, "/");
  const std::string where = "line " + std::to_string(line) + " of the scene (expanded includes)" +
                            (path.empty() ? std::string(", at the top level") : ", in subsection '" + path + "'");
  if (std::regex_search(message, m, std::regex(R"(No entry with name <(.*)> was declared)")))
    return where + ": there is no entry '" + base::printable_excerpt(m[1], 80) + "'" + nearest_declared_hint(prm, path, m[1]);
  if (std::regex_search(message, m, std::regex(R"(There is no such subsection to be entered: (.*)$)")))
    {
      // The subsection is opened at this line: it is not part of the path yet.
      const std::string name = base::trim(m[1]);
      return where + ": there is no subsection '" + base::printable_excerpt(name, 80) + "'" + nearest_declared_hint(prm, path, name);
    }
  if (const std::string explained = explained_pattern_mismatch(message); !explained.empty()) return where + ": " + explained;
  return message;
}
} // namespace

void SceneFile::parse(ParameterHandler &prm, const bool skip_undefined) const
{
  try
    {
      if (json)
        {
          std::istringstream in(with_demanglable_keys(text));
          prm.parse_input_from_json(in, skip_undefined);
        }
      else
        prm.parse_input_from_string(text, "", skip_undefined);
    }
  catch (const dealii::ExceptionBase &e)
    {
      const std::string message = base::parse_error_text(e);
      throw InputError("", base::printable_excerpt(json ? message : explained_parse_error(message, text, prm), 400), name);
    }
  try
    {
      apply_overrides(prm, overrides, "", skip_undefined);
      if (!skip_undefined) make_file_entries_absolute(prm, directory);
    }
  catch (const InputError &e)
    {
      throw e.in_file(name);
    }
  refuse_subnormal_numbers(prm, name);
}

std::vector<ParameterOverride> SceneFile::overrides_of(const std::string &body_name) const
{
  std::vector<ParameterOverride> own;
  for (auto o : overrides)
    if (o.scope == "Body " + body_name)
      {
        o.scope.clear();
        own.push_back(o);
      }
  return own;
}

namespace
{
/// True if @p text holds anything besides blanks and comments ('#' to the end of a line in a
/// .prm file; a JSON file must hold more than an empty object).
bool has_entries(const std::string &text, const bool json)
{
  if (json)
    {
      std::string compact;
      for (const char c : text)
        if (!std::isspace(static_cast<unsigned char>(c))) compact += c;
      return !compact.empty() && compact != "{}";
    }
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line))
    {
      const auto first = line.find_first_not_of(" \t\r");
      if (first != std::string::npos && line[first] != '#') return true;
    }
  return false;
}
} // namespace

SceneFile SceneFile::from_text(const std::string &text, const std::string &directory, const bool json,
                               const std::vector<ParameterOverride> &overrides)
{
  SceneFile scene;
  scene.name = "<string>";
  scene.overrides = overrides;
  scene.directory = directory;
  scene.json = json;
  if (json)
    {
      if (json_depth(text) > max_json_depth)
        throw InputError("", "JSON nested more than " + std::to_string(max_json_depth) + " deep", scene.name);
      scene.text = text;
    }
  else
    scene.text = expand_includes(text, scene.name, directory, 0);
  // An empty file parsed to every default: the default scene of its model ran, exit 0.
  if (!has_entries(scene.text, json))
    throw InputError("", "holds no entries (only blanks and comments): write the scene (doc/user_guide.md), or run "
                         "'flextrack' with no arguments for the default scene", scene.name);
  scene.lists = std::make_shared<ParameterHandler>();
  declare_first_pass(*scene.lists);
  scene.parse(*scene.lists, true);
  scene.model = scene.lists->get("Model");
  return scene;
}

SceneFile SceneFile::read(const std::string &file, const std::vector<ParameterOverride> &overrides)
{
  const auto parent = fs::path(file).parent_path().string();
  const bool json = fs::path(file).extension() == ".json";
  try
    {
      auto scene = from_text(read_bytes(file, "parameter file"), parent.empty() ? "." : parent, json, overrides);
      scene.name = file;
      return scene;
    }
  catch (const InputError &e)
    {
      throw e.file().empty() || e.file() == "<string>" ? e.in_file(file) : e;
    }
}
namespace
{
/// @p name as deal.II mangles it in JSON keys ('_' -> "_5f"; names hold no other character it mangles).
std::string mangled_key(const std::string &name)
{
  std::string mangled;
  for (const char c : name) mangled += c == '_' ? std::string("_5f") : std::string(1, c);
  return mangled;
}
} // namespace

SceneFile SceneFile::with_mangled_json_keys(const std::vector<std::string> &subsections) const
{
  SceneFile scene = *this;
  if (!json) return scene;
  for (const auto &key : subsections)
    {
      const std::string raw = "\"" + key + "\"", mangled = "\"" + mangled_key(key) + "\"";
      if (raw == mangled) continue;
      for (std::size_t at = scene.text.find(raw); at != std::string::npos; at = scene.text.find(raw, at + mangled.size()))
        scene.text.replace(at, raw.size(), mangled);
    }
  return scene;
}

bool SceneFile::has_subsection(const std::string &subsection) const
{
  if (json)
    {
      // JSON written by deal.II's ParameterHandler has its keys mangled: '_' becomes "_5f" (the
      // only character of a name, base/names.h, that it mangles). Either spelling counts.
      return text.find("\"" + subsection + "\"") != std::string::npos ||
             text.find("\"" + mangled_key(subsection) + "\"") != std::string::npos;
    }
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line))
    {
      const auto hash = line.find('#');
      const std::string code = base::trim(hash == std::string::npos ? line : line.substr(0, hash));
      if (code.rfind("subsection", 0) == 0 && code.size() > 10 && std::isspace(static_cast<unsigned char>(code[10])) &&
          base::trim(code.substr(10)) == subsection)
        return true;
    }
  return false;
}
} // namespace flextrack::io
