#include <fem/arm.h>
#include <base/text.h>
#include <base/input_error.h>
#include <geometry/built_geometry.h>
#include <geometry/spline.h>

#include <algorithm>
#include <cctype>
#include <functional>
#include <map>
#include <sstream>

namespace flextrack::fem
{
using dealii::ParameterHandler;

std::string Arm::supports_text() const
{
  static const char *kind_name[] = {"free", "pinned", "clamped"};
  std::ostringstream t;
  const double L = curve ? curve->length() : 0;
  for (std::size_t i = 0; i < supports.size(); ++i)
    {
      const auto &p = supports[i];
      t << (i ? ", " : "");
      if (i == 0 && p.s == 0) t << "start ";
      else if (i == 1 && p.s == L) t << "end ";
      else t << "s = " << p.s << " m ";
      t << kind_name[static_cast<int>(p.kind)];
    }
  return t.str();
}

SupportKind parse_support_kind(const std::string &text, const std::string &entry)
{
  std::string t = text;
  t.erase(0, t.find_first_not_of(" \t"));
  t.erase(t.find_last_not_of(" \t") + 1);
  if (t == "clamped") return SupportKind::clamped;
  if (t == "pinned") return SupportKind::pinned;
  if (t == "free") return SupportKind::free;
  throw InputError(entry, "unknown support '" + base::printable_excerpt(t) + "'; allowed: clamped, pinned, free");
}

void check_arm_cell_count(const Arm &arm, const double n_cells, const std::string &how)
{
  if (n_cells <= max_arm_cells) return;
  const double dofs = 6 * (arm.degree * n_cells + 1), bytes = 2048 * dofs;
  const char *units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double amount = bytes;
  int u = 0;
  for (; amount >= 1024 && u < 6; ++u) amount /= 1024;
  std::ostringstream m;
  m.precision(3);
  if (n_cells < 1e15)
    m << static_cast<long long>(n_cells);
  else
    m << n_cells;
  m << " cells of degree " << arm.degree << how << " would need about " << amount
    << " " << units[u] << " of memory (" << dofs << " degrees of freedom); allowed: at most "
    << static_cast<long>(max_arm_cells) << " cells";
  throw InputError(arm.section_name + "/Mesh/Number of elements", m.str());
}

namespace
{
/// Writes, as parameter-file text, every entry that @p declare declares (in a handler of its
/// own, so nothing else of @p prm), with the value @p prm holds; @p prm is in the subsection
/// where @p declare would declare. A top-level subsection is kept only if @p keep says so;
/// @p replace gives other values for some entries ("Sub/Entry" -> value).
void print_entries(ParameterHandler &prm, const std::function<void(ParameterHandler &)> &declare,
                   const std::function<bool(const std::string &)> &keep, const std::map<std::string, std::string> &replace,
                   std::ostream &out, const std::string &indent)
{
  ParameterHandler declared;
  declare(declared);
  std::ostringstream skeleton;
  declared.print_parameters(skeleton, ParameterHandler::ShortPRM);
  std::istringstream lines(skeleton.str());
  std::vector<std::string> path; // subsections entered in prm
  unsigned int skipped = 0;      // depth inside a subsection that is not kept
  for (std::string line; std::getline(lines, line);)
    {
      const std::string t = base::trim(line);
      const std::string pad = indent + std::string(2 * path.size(), ' ');
      if (t.rfind("subsection ", 0) == 0)
        {
          const std::string name = base::trim(t.substr(11));
          if (skipped > 0 || (path.empty() && !keep(name)))
            ++skipped;
          else
            {
              out << pad << "subsection " << name << "\n";
              prm.enter_subsection(name);
              path.push_back(name);
            }
        }
      else if (t == "end")
        {
          if (skipped > 0)
            --skipped;
          else
            {
              prm.leave_subsection();
              path.pop_back();
              out << indent << std::string(2 * path.size(), ' ') << "end\n";
            }
        }
      else if (t.rfind("set ", 0) == 0 && skipped == 0)
        {
          const std::string name = base::trim(t.substr(4, t.find('=') - 4));
          std::string key;
          for (const auto &p : path) key += p + "/";
          const auto r = replace.find(key + name);
          out << pad << "set " << name << " = " << (r == replace.end() ? prm.get(name) : r->second) << "\n";
        }
    }
}

/// "subsection Curve" (the chosen kind only) as parameter-file text, in the arm's Curve
/// subsection of @p prm: a spline's points file is read and its points written inline, at full
/// precision (17 digits read back to the same doubles), so that the text needs no file.
std::string curve_text(ParameterHandler &prm, const geometry::ParseContext &where)
{
  std::string kind = prm.get("Kind");
  std::map<std::string, std::string> replace;
  prm.enter_subsection("Spline");
  std::string file = base::trim(prm.get("Points file"));
  const bool inline_given = !base::trim(prm.get("Inline points")).empty();
  prm.leave_subsection();
  // Both given: left as it is, so that the text matches no built geometry and parse_curve
  // refuses the pair (it would otherwise equal the text of the file alone).
  if (kind == "spline" && !file.empty() && !inline_given)
    {
      if (file[0] != '/' && !where.directory.empty()) file = where.directory + "/" + file;
      std::ostringstream points;
      points.precision(17);
      for (const auto &x : geometry::read_points(file, where.section + "/Spline/Points file"))
        points << (points.tellp() > 0 ? "; " : "") << x[0] << " " << x[1] << " " << x[2];
      replace = {{"Spline/Points file", ""}, {"Spline/Inline points", points.str()}};
    }
  auto same_kind = [&kind](const std::string &subsection) {
    std::string lower = subsection;
    for (auto &c : lower) c = std::tolower(static_cast<unsigned char>(c));
    return lower == kind;
  };
  std::ostringstream text;
  text << "subsection Curve\n";
  print_entries(prm, geometry::declare_curve_parameters, same_kind, replace, text, "  ");
  text << "end\n";
  return text.str();
}
} // namespace

void Arm::declare_parameters(ParameterHandler &prm, const std::string &section)
{
  prm.enter_subsection(section);
  prm.enter_subsection("Curve");
  geometry::declare_curve_parameters(prm);
  prm.leave_subsection();
  geometry::SectionFrame::declare_parameters(prm);
  CrossSection::declare_parameters(prm);
  Material::declare_parameters(prm);
  prm.enter_subsection("Supports");
  const auto kinds = dealii::Patterns::Selection("clamped|pinned|free");
  // Free by default (issue 25, item 5): an arm is held only where the scene says so (a support
  // here, a tie to a solid, a joint at an interface); the log lists every arm's supports.
  prm.declare_entry("Start", "free", kinds,
                    "Support at s = 0: 'clamped' (3 displacements and 3 rotations fixed), 'pinned' "
                    "(3 displacements fixed), 'free' (the default: an arm held by a tie or by a joint at an "
                    "interface needs no support; a cantilever says 'clamped').");
  prm.declare_entry("End", "free", kinds, "Support at the far end s = L (same choices).");
  prm.declare_entry("Intermediate", "", dealii::Patterns::Anything(),
                    "Further supports as 'arc length [m]: kind' separated by ';', e.g. '0.5: pinned; "
                    "1.2: clamped'. 0 <= s <= L; a mesh node is placed at each; at most 1000.");
  prm.leave_subsection();
  prm.enter_subsection("Mesh");
  prm.declare_entry("Number of elements", "16", dealii::Patterns::Integer(1),
                    "Number of beam elements along the arm on the coarsest mesh [-], 1 to 200000 (also after "
                    "the refinements of 'converge': about 2 KiB of memory per degree of freedom).");
  prm.declare_entry("Element degree", "2", dealii::Patterns::Integer(1, 3),
                    "Polynomial degree of the curved beam element [-]: 1, 2 or 3.");
  prm.leave_subsection();
  prm.leave_subsection();
}

Arm Arm::parse_parameters(ParameterHandler &prm, const std::string &directory, const std::string &section)
{
  Arm arm;
  arm.section_name = section;
  // An InputError ends the run, so subsections need not be left on the way out.
  prm.enter_subsection(section);
  {
      // The text first: a curve and frame built before from the same text (the same arm in an
      // earlier case, the rigid reference run) are taken as they are. They were checked then.
      prm.enter_subsection("Curve");
      arm.geometry_parameters = curve_text(prm, {section + "/Curve", directory});
      prm.leave_subsection();
      std::ostringstream frame_text;
      print_entries(prm, geometry::SectionFrame::declare_parameters, [](const std::string &) { return true; }, {},
                    frame_text, "");
      arm.geometry_parameters += frame_text.str();
      if (const auto built = geometry::built_geometry(arm.geometry_parameters))
        {
          arm.curve = built->curve;
          arm.frame = built->frame;
        }
      else
        {
          prm.enter_subsection("Curve");
          arm.curve = geometry::parse_curve(prm, {section + "/Curve", directory});
          prm.leave_subsection();
          arm.frame = std::make_shared<geometry::SectionFrame>(
            geometry::SectionFrame::parse_parameters(prm, arm.curve, {section, directory}));
          geometry::remember_built_geometry(arm.geometry_parameters, {arm.curve, arm.frame});
        }
      arm.material = Material::parse_parameters(prm, section);
      arm.section = CrossSection::parse_parameters(prm, section, arm.material.poisson_ratio);

      prm.enter_subsection("Supports");
      const double L = arm.curve->length();
      arm.supports.push_back({0.0, parse_support_kind(prm.get("Start"), section + "/Supports/Start")});
      arm.supports.push_back({L, parse_support_kind(prm.get("End"), section + "/Supports/End")});
      const std::string entry = section + "/Supports/Intermediate";
      const auto intermediate = base::named_items(prm.get("Intermediate"), entry, "arc length: kind");
      if (intermediate.size() > max_intermediate_supports)
        throw InputError(entry, std::to_string(intermediate.size()) + " supports; at most " +
                                  std::to_string(max_intermediate_supports) + " are allowed");
      for (const auto &[where, kind] : intermediate)
        {
          const double s = base::parse_number(where, entry, "an arc length [m]");
          if (s < 0 || s > L * (1 + 1e-12))
            {
              std::ostringstream m;
              m << "support at s = " << s << " m lies beyond the arm (its length is L = " << L
                << " m); allowed: 0 <= s <= L";
              throw InputError(entry, m.str());
            }
          arm.supports.push_back({std::min(s, L), parse_support_kind(kind, entry)});
        }
      prm.leave_subsection();

      prm.enter_subsection("Mesh");
      const long n_elements = prm.get_integer("Number of elements");
      arm.degree = prm.get_integer("Element degree");
      prm.leave_subsection();
      check_arm_cell_count(arm, n_elements, "");
      arm.n_elements = n_elements;
  }
  prm.leave_subsection();
  return arm;
}
} // namespace flextrack::fem
