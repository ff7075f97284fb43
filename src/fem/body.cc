#include <base/names.h>
#include <base/text.h>
#include <fem/body.h>
#include <geometry/curve_library.h>
#include <base/input_error.h>

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>

namespace flextrack::fem
{
using dealii::ParameterHandler;

namespace
{
using base::words;

// Sanity limits of a body's lists and numbers (judgements, stated in the entries' documentation).
constexpr std::size_t max_arms = 100;
constexpr std::size_t max_items = 1000; // ties, interfaces, output points, point masses
const geometry::NumberRange radius_range{0, geometry::max_coordinate, false, "m"};
const geometry::NumberRange coordinate_range{-geometry::max_coordinate, geometry::max_coordinate, true, "m"};
const geometry::NumberRange mass_range{0, 1e9, false, "kg"};
const geometry::NumberRange inertia_range{0, 1e12, true, "kg m^2"};

/// A number of an item's text: finite and within @p range; InputError naming @p entry and the item.
double number(const std::string &word, const std::string &entry, const std::string &what,
              const geometry::NumberRange &range)
{
  const double v = base::parse_number(word, entry, what);
  const bool above = range.lower_included ? v >= range.lower : v > range.lower;
  if (!(above && v >= range.smallest && v <= range.upper))
    {
      std::ostringstream m;
      m << what << " must be " << range.text(v) << " (got " << v << ")";
      throw InputError(entry, m.str());
    }
  return v;
}

/// The items of a list entry, at most max_items of them.
std::vector<std::pair<std::string, std::string>> named_items(const std::string &text, const std::string &entry,
                                                             const std::string &form)
{
  auto items = base::named_items(text, entry, form);
  if (items.size() > max_items)
    throw InputError(entry, std::to_string(items.size()) + " items; at most " + std::to_string(max_items) +
                              " are allowed");
  return items;
}

/// "within R" or "set NAME", starting at words[i].
NodeRegion parse_region(const std::vector<std::string> &w, const size_t i, const std::string &entry,
                        const std::optional<Solid> &solid)
{
  NodeRegion r;
  if (i + 2 != w.size() || (w[i] != "within" && w[i] != "set"))
    throw InputError(entry, "a solid region is 'within RADIUS' (all solid nodes within RADIUS [m] of the point) or "
                            "'set NAME' (a node set of the mesh)");
  r.text = base::printable_excerpt(w[i] + " " + w[i + 1]); // for messages only
  if (w[i] == "within")
    r.radius = number(w[i + 1], entry, "the radius in '" + r.text + "'", radius_range);
  else
    {
      r.node_set = w[i + 1];
      std::transform(r.node_set.begin(), r.node_set.end(), r.node_set.begin(), ::toupper);
      if (solid && !solid->mesh->node_sets.count(r.node_set))
        {
          std::string known;
          for (const auto &[name, nodes] : solid->mesh->node_sets) known += (known.empty() ? "" : ", ") + name;
          throw InputError(entry, "the mesh " + solid->mesh->source + " has no node set '" +
                                    base::printable_excerpt(r.node_set) + "'; it has: " +
                                    (known.empty() ? "none" : base::printable_excerpt(known, 200)));
        }
    }
  return r;
}
} // namespace

int Body::arm_index(const std::string &name) const
{
  const auto it = std::find(arm_names.begin(), arm_names.end(), name);
  return it == arm_names.end() ? -1 : it - arm_names.begin();
}

int Body::interface_index(const std::string &name) const
{
  for (unsigned int i = 0; i < interfaces.size(); ++i)
    if (interfaces[i].name == name) return i;
  return -1;
}

void Body::declare_arm_list(ParameterHandler &prm)
{
  prm.enter_subsection("Body");
  prm.declare_entry("Arms", "", dealii::Patterns::Anything(),
                    "Names of the body's curved arms, separated by commas (letters, digits, '_'); each arm "
                    "NAME is described in its own 'subsection Arm NAME'. Empty: no arms. At most 100 arms.");
  prm.leave_subsection();
}

std::vector<std::string> Body::parse_arm_list(ParameterHandler &prm)
{
  prm.enter_subsection("Body");
  const std::string text = prm.get("Arms");
  prm.leave_subsection();
  auto names = base::parse_name_list(text, "Body/Arms", "arm name");
  if (names.size() > max_arms)
    throw InputError("Body/Arms", std::to_string(names.size()) + " arms; at most " + std::to_string(max_arms) +
                                    " are allowed");
  return names;
}

void Body::declare_parameters(ParameterHandler &prm, const std::vector<std::string> &arm_names)
{
  declare_arm_list(prm);
  prm.enter_subsection("Body");
  prm.declare_entry("Solid", "auto", dealii::Patterns::Selection("auto|true|false"),
                    "Whether the body has a solid part, described in 'subsection Solid' [-]: 'auto' (the "
                    "default): a solid part when the file has a 'subsection Solid' or lists no arms, none for a "
                    "body of arms only (a body of arms used to get the default solid, a 1 x 0.1 x 0.1 m steel "
                    "box of 78.5 kg tied to nothing); 'true' or 'false' say it.");
  prm.declare_entry("Ties", "", dealii::Patterns::Anything(),
                    "Arm roots (s = 0) tied to the solid, separated by ';': 'ARM: KIND, REGION' with KIND "
                    "'rigid' (the region moves rigidly with the arm root) or 'distributing' (the arm root "
                    "follows the region's mean translation and least-squares rotation, adding no stiffness), "
                    "and REGION 'within R' (solid nodes within R [m] of the arm's start point) or 'set NAME' "
                    "(a node set of the mesh), 0 < R <= 1e6. Example: 'boom: rigid, within 0.012'.");
  prm.declare_entry("Interfaces", "", dealii::Patterns::Anything(),
                    "Named points where joints attach, 6 dofs each, separated by ';': 'NAME: arm ARM at S' "
                    "(the arm's node at arc length S [m], 0 <= S <= L) or 'NAME: point X Y Z, REGION' (a point "
                    "[m], coordinates at most 1e6 m in size, tied rigidly to the solid nodes of REGION: 'within R' "
                    "or 'set NAME'). At most 1000.");
  prm.declare_entry("Output points", "", dealii::Patterns::Anything(),
                    "Points whose motion is reported and exported (e.g. as MBDyn FEM nodes) but where nothing "
                    "attaches, separated by ';': 'NAME: arm ARM at S' or 'NAME: point X Y Z, within R' / 'NAME: "
                    "point X Y Z, set NAME'. A point on the solid follows the region's mean translation and "
                    "least-squares rotation and adds no stiffness. At most 1000.");
  prm.declare_entry("Point masses", "", dealii::Patterns::Anything(),
                    "Rigid masses at interface points, separated by ';': 'INTERFACE: m' or 'INTERFACE: m, Jxx, "
                    "Jyy, Jzz' with mass m [kg], 0 < m <= 1e9, and principal inertias about the point "
                    "[kg m^2], 0 <= J <= 1e12 (body axes). At most 1000.");
  prm.leave_subsection();
  Solid::declare_parameters(prm);
  for (const auto &name : arm_names) Arm::declare_parameters(prm, "Arm " + name);
}

Body Body::parse_parameters(ParameterHandler &prm, const std::string &directory, const bool solid_described)
{
  Body body;
  body.arm_names = parse_arm_list(prm);
  prm.enter_subsection("Body");
  const std::string solid = prm.get("Solid");
  const bool has_solid = solid == "auto" ? solid_described || body.arm_names.empty() : solid == "true";
  const std::string ties = prm.get("Ties"), interfaces = prm.get("Interfaces"), masses = prm.get("Point masses"),
                    outputs = prm.get("Output points");
  prm.leave_subsection();
  if (has_solid) body.solid = Solid::parse_parameters(prm, directory);
  for (const auto &name : body.arm_names) body.arms.push_back(Arm::parse_parameters(prm, directory, "Arm " + name));
  if (!has_solid && body.arms.empty())
    throw InputError("Body/Solid", "the body has neither a solid part nor arms; set 'Solid = true' or list arms in 'Arms'");

  std::set<std::string> tied;
  for (const auto &[arm, spec] : named_items(ties, "Body/Ties", "ARM: rigid|distributing, within R|set NAME"))
    {
      const std::string entry = "Body/Ties";
      if (body.arm_index(arm) < 0) throw InputError(entry, "'" + base::printable_excerpt(arm) + "' is not an arm of the body (listed in Body/Arms)");
      if (!body.solid) throw InputError(entry, "arm '" + arm + "' is tied to the solid, but the body has no solid part");
      if (!tied.insert(arm).second) throw InputError(entry, "arm '" + arm + "' is tied twice");
      const auto w = words(spec);
      if (w.empty() || (w[0] != "rigid" && w[0] != "distributing"))
        throw InputError(entry, "tie of '" + arm + "': the kind must be 'rigid' or 'distributing'");
      body.ties.push_back({arm, w[0] == "rigid" ? TieKind::rigid : TieKind::distributing,
                           parse_region(w, 1, entry, body.solid)});
    }

  // Interfaces and output points share one grammar.
  auto parse_points = [&](const std::string &text, const std::string &entry, const std::string &kind,
                          std::vector<InterfacePoint> &points) {
    for (const auto &[name, spec] : named_items(text, entry, "NAME: arm ARM at S | point X Y Z, within R"))
      {
        if (!base::is_valid_name(name))
          throw InputError(entry, kind + " name '" + base::printable_excerpt(name) + "' is not allowed: a name has " +
                                    base::name_rule());
        if (body.interface_index(name) >= 0 ||
            std::any_of(body.output_points.begin(), body.output_points.end(), [&](const auto &o) { return o.name == name; }))
          throw InputError(entry, kind + " '" + name + "' is defined twice (names are shared by interfaces and output points)");
        InterfacePoint p;
        p.name = name;
        const auto w = words(spec);
        if (w.size() == 4 && w[0] == "arm" && w[2] == "at")
          {
            p.arm = w[1];
            const int a = body.arm_index(p.arm);
            if (a < 0) throw InputError(entry, kind + " '" + name + "': '" + base::printable_excerpt(p.arm) + "' is not an arm of the body");
            p.s = base::parse_number(w[3], entry, "arc length [m]");
            const double L = body.arms[a].curve->length();
            if (p.s < 0 || p.s > L * (1 + 1e-12))
              {
                std::ostringstream m;
                m << kind << " '" << name << "' at s = " << p.s << " m lies on no part: arm '" << p.arm
                  << "' runs over 0 <= s <= " << L << " m";
                throw InputError(entry, m.str());
              }
            p.s = std::min(p.s, L);
          }
        else if (w.size() >= 4 && w[0] == "point")
          {
            for (unsigned int d = 0; d < 3; ++d)
              p.position[d] = number(w[1 + d], entry, kind + " '" + name + "': coordinate", coordinate_range);
            if (!body.solid) throw InputError(entry, kind + " '" + name + "' is a point on the solid, but the body has no solid part");
            p.region = parse_region(w, 4, entry, body.solid);
          }
        else
          throw InputError(entry, kind + " '" + name + "': '" + base::printable_excerpt(spec) + "' is neither 'arm ARM at S' nor 'point X Y Z, within R' "
                                  "nor 'point X Y Z, set NAME'");
        points.push_back(p);
      }
  };
  parse_points(interfaces, "Body/Interfaces", "interface", body.interfaces);
  parse_points(outputs, "Body/Output points", "output point", body.output_points);

  for (const auto &[at, spec] : named_items(masses, "Body/Point masses", "INTERFACE: m, Jxx, Jyy, Jzz"))
    {
      const std::string entry = "Body/Point masses";
      if (body.interface_index(at) < 0) throw InputError(entry, "'" + base::printable_excerpt(at) + "' is not an interface of the body (Body/Interfaces)");
      const auto w = words(spec);
      if (w.size() != 1 && w.size() != 4) throw InputError(entry, "point mass at '" + at + "': give 'm' or 'm, Jxx, Jyy, Jzz'");
      PointMass m;
      m.interface = at;
      m.mass = number(w[0], entry, "point mass at '" + at + "': the mass", mass_range);
      for (unsigned int d = 0; d + 1 < w.size(); ++d)
        m.inertia[d][d] = number(w[1 + d], entry, "point mass at '" + at + "': the inertia", inertia_range);
      body.point_masses.push_back(m);
    }
  return body;
}
} // namespace flextrack::fem
