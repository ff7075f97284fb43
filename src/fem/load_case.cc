#include <base/input_error.h>
#include <base/text.h>
#include <fem/load_case.h>
#include <geometry/curve_library.h>

#include <deal.II/base/quadrature_lib.h>

#include <algorithm>
#include <cctype>
#include <iomanip>
#include <sstream>

namespace flextrack::fem
{
using dealii::ParameterHandler;
using dealii::Tensor;

namespace
{
// Sanity limits: beyond them a value is a unit mistake, and 1e300 would overflow the solution.
const geometry::NumberRange force_range{-1e12, 1e12, true, "N"};
const geometry::NumberRange moment_range{-1e12, 1e12, true, "N m"};
const geometry::NumberRange line_load_range{-1e12, 1e12, true, "N/m"};
const geometry::NumberRange gravity_range{-1e6, 1e6, true, "m/s^2"};
const geometry::NumberRange pressure_range{-1e12, 1e12, true, "Pa"};
const geometry::NumberRange support_displacement_range{-1e6, 1e6, true, "m"};
const geometry::NumberRange support_rotation_range{-1e6, 1e6, true, "rad"};

std::string section_of(const std::string &name) { return "Load case " + name; }

/// An arc length [m] on @p arm, 0 <= s <= L (a hair beyond L is L).
double arc_length(const std::string &word, const std::string &entry, const std::string &what, const Arm &arm)
{
  const double s = base::parse_number(word, entry, "an arc length [m]");
  const double L = arm.curve->length();
  if (s < 0 || s > L * (1 + 1e-12))
    {
      std::ostringstream m;
      m << what << " at s = " << s << " m lies beyond the arm (its length is L = " << L
        << " m); allowed: 0 <= s <= L";
      throw InputError(entry, m.str());
    }
  return std::min(s, L);
}

/// Three numbers "x y z" (blanks or commas), each within @p range.
Tensor<1, 3> vector3(const std::string &text, const std::string &entry, const std::string &what,
                     const geometry::NumberRange &range)
{
  const auto w = base::words(text);
  if (w.size() != 3)
    throw InputError(entry, what + " '" + base::printable_excerpt(text) + "' is not three numbers 'x y z' [" +
                              range.unit + "]");
  Tensor<1, 3> v;
  for (unsigned int d = 0; d < 3; ++d)
    v[d] = geometry::checked_number(base::parse_number(w[d], entry, "a component [" + range.unit + "]"), entry, range);
  return v;
}

/// @p name (upper-cased) if @p solid has that node set; InputError naming @p entry otherwise.
std::string node_set(const std::string &name, const std::string &entry, const Solid *solid)
{
  if (!solid)
    throw InputError(entry, "the scene has no solid: node sets apply to 'Model = solid' scenes and bodies with a solid");
  std::string upper = name;
  for (auto &c : upper) c = std::toupper(static_cast<unsigned char>(c));
  const auto &sets = solid->mesh->node_sets;
  if (sets.count(upper)) return upper;
  std::string allowed;
  for (const auto &[set, nodes] : sets) allowed += (allowed.empty() ? "" : ", ") + set;
  throw InputError(entry, "node set '" + base::printable_excerpt(name) + "' does not exist in " + solid->mesh->source +
                            "; allowed: " + (allowed.empty() ? "(the mesh has no node sets)" : allowed));
}

/// Names for an "allowed:" list.
std::string joined(const std::vector<std::string> &names)
{
  std::string text;
  for (const auto &n : names) text += (text.empty() ? "" : ", ") + n;
  return text.empty() ? "(none)" : text;
}

/// The body's arm called @p name (InputError naming @p entry and the arms otherwise).
unsigned int body_arm(const std::string &name, const std::string &entry, const Body &body)
{
  const int a = body.arm_index(name);
  if (a < 0)
    throw InputError(entry, "'" + base::printable_excerpt(name) + "' is not an arm of the body; allowed: " +
                              joined(body.arm_names));
  return a;
}

/// A place "S" on the arm of an arm scene, or "ARM S" / "NAME" (interface or output point) on a
/// body. InputError naming @p entry if it is none of these.
LoadPoint load_point(const std::string &where, const std::string &entry, const std::string &what, const Arm *arm,
                     const Body *body)
{
  LoadPoint p;
  const auto w = base::words(where);
  if (arm)
    {
      if (w.size() != 1) throw InputError(entry, what + " at '" + base::printable_excerpt(where) + "': allowed: an arc length S [m]");
      p.s = arc_length(w[0], entry, what, *arm);
      std::ostringstream label;
      label << "s = " << std::setprecision(8) << p.s << " m";
      p.label = label.str();
      return p;
    }
  if (!body)
    throw InputError(entry, "the scene has no arm: point and line loads at arc lengths apply to 'Model = arm' and "
                            "'Model = body' scenes");
  if (w.size() == 2)
    {
      p.arm = body_arm(w[0], entry, *body);
      p.s = arc_length(w[1], entry, what + " on arm '" + w[0] + "'", body->arms[p.arm]);
      p.label = w[0] + " " + w[1];
      return p;
    }
  std::vector<std::string> names;
  for (const auto &i : body->interfaces) names.push_back(i.name);
  for (const auto &o : body->output_points) names.push_back(o.name);
  if (w.size() == 1 && std::find(names.begin(), names.end(), w[0]) != names.end())
    {
      p.point = p.label = w[0];
      return p;
    }
  throw InputError(entry, what + " at '" + base::printable_excerpt(where) +
                            "': allowed: 'ARM S' (an arm of the body and an arc length [m] on it) or an interface or "
                            "output point of the body: " + joined(names));
}

/// The support at arc length @p where of @p arm, which must fix at least the displacements;
/// its prescribed u (3 numbers) or u and theta (6 numbers, a clamped support only).
SupportDisplacement arm_support_displacement(const std::string &where, const std::string &value,
                                            const std::string &entry, const Arm &arm)
{
  SupportDisplacement d;
  d.label = base::trim(where);
  d.s = arc_length(where, entry, "support displacement", arm);
  const double L = arm.curve->length();
  const Support *support = nullptr;
  std::string allowed;
  for (const auto &candidate : arm.supports)
    if (candidate.kind != SupportKind::free)
      {
        std::ostringstream o;
        o << std::setprecision(8) << candidate.s;
        allowed += (allowed.empty() ? "" : ", ") + o.str();
        if (std::abs(candidate.s - d.s) <= 1e-9 * L && (!support || candidate.kind == SupportKind::clamped))
          support = &candidate;
      }
  if (!support)
    throw InputError(entry, "there is no pinned or clamped support at s = " + base::printable_excerpt(where) +
                              " m; allowed: the arc lengths [m] of the supports: " +
                              (allowed.empty() ? "(none)" : allowed));
  const auto w = base::words(value);
  if (w.size() != 3 && !(w.size() == 6 && support->kind == SupportKind::clamped))
    throw InputError(entry, "support displacement at s = " + d.label + " m: '" + base::printable_excerpt(value) +
                              "'; allowed: 'ux uy uz' [m]" +
                              (support->kind == SupportKind::clamped ? " or 'ux uy uz theta_x theta_y theta_z' [m, rad]"
                                                                     : " (the support is pinned: no rotation)"));
  for (std::size_t k = 0; k < w.size(); ++k)
    {
      const auto &range = k < 3 ? support_displacement_range : support_rotation_range;
      d.value.push_back(geometry::checked_number(
        base::parse_number(w[k], entry, "a component [" + range.unit + "]"), entry, range));
    }
  return d;
}

/// The support of @p solid written @p where (a node set name or a plane 'x = value', as in
/// Solid/Supports) and its prescribed u (3 numbers, zero in the components it does not fix).
SupportDisplacement solid_support_displacement(const std::string &where, const std::string &value,
                                              const std::string &entry, const Solid &solid)
{
  SupportDisplacement d;
  d.label = base::trim(where);
  const Tensor<1, 3> u = vector3(value, entry, "support displacement", support_displacement_range);
  const SolidSupport place = parse_support_place(d.label, entry);
  // Every support written at this place (a place may be listed more than once, e.g.
  // 'x = 0: x; x = 0: y'): the value may be non-zero only in the components one of them fixes.
  std::string allowed;
  std::array<bool, 3> fixed{{false, false, false}};
  for (unsigned int k = 0; k < solid.supports.size(); ++k)
    {
      const auto &support = solid.supports[k];
      allowed += (allowed.empty() ? "" : ", ") + support.text.substr(0, support.text.find(':'));
      if (!same_place(place, support)) continue;
      d.supports.push_back(k);
      for (unsigned int c = 0; c < 3; ++c) fixed[c] = fixed[c] || support.fixed[c];
    }
  if (!d.supports.empty())
    {
      for (unsigned int c = 0; c < 3; ++c)
        if (!fixed[c] && u[c] != 0)
          throw InputError(entry, "the support '" + d.label + "' does not fix the " + std::string(1, "xyz"[c]) +
                                    " component, so it cannot prescribe it; allowed: 0 there");
      d.value = {u[0], u[1], u[2]};
      return d;
    }
  throw InputError(entry, "'" + base::printable_excerpt(where) + "' is not a support of the solid; allowed: " +
                            (allowed.empty() ? "(the solid has no supports)" : allowed));
}

/// The ';'-separated items of an entry, at most max_load_items of them.
std::vector<std::pair<std::string, std::string>> items(ParameterHandler &prm, const std::string &name,
                                                       const std::string &entry, const std::string &form)
{
  const auto list = base::named_items(prm.get(name), entry, form);
  if (list.size() > max_load_items)
    throw InputError(entry, std::to_string(list.size()) + " items; at most " + std::to_string(max_load_items) +
                              " are allowed");
  return list;
}

/// Composite Gauss rule on [a, b]: the centre line is smooth, 64 panels of 8 points integrate
/// its position to round-off for any curve the scene files allow.
template <typename F>
void integrate(const double a, const double b, F &&f)
{
  const dealii::QGauss<1> rule(8);
  const unsigned int panels = 64;
  const double h = (b - a) / panels;
  for (unsigned int k = 0; k < panels; ++k)
    for (unsigned int q = 0; q < rule.size(); ++q) f(a + h * (k + rule.point(q)[0]), h * rule.weight(q));
}
} // namespace

void LoadCase::declare_parameters(ParameterHandler &prm, const std::vector<std::string> &names)
{
  for (const auto &name : names)
    {
      prm.enter_subsection(section_of(name));
      prm.declare_entry("Point forces", "", dealii::Patterns::Anything(),
                        "Arm: forces at arc lengths, separated by ';': 'S: Fx Fy Fz' with S [m], 0 <= S <= L, and the "
                        "force [N] in global axes, each component at most 1e12 N in size. A mesh node is placed at "
                        "each S. Body: 'ARM S: Fx Fy Fz' (an arm of the body, S [m] on it; consistent nodal loads "
                        "between nodes) or 'POINT: Fx Fy Fz' (an interface or output point). At most 1000.");
      prm.declare_entry("Point moments", "", dealii::Patterns::Anything(),
                        "Arm: moments at arc lengths, separated by ';': 'S: Mx My Mz' with S [m], 0 <= S <= L, and the "
                        "moment [N m] in global axes, each component at most 1e12 N m in size. Body: 'ARM S: ...' or "
                        "'POINT: ...' as for the forces. At most 1000.");
      prm.declare_entry("Line loads", "", dealii::Patterns::Anything(),
                        "Arm: uniform distributed forces, separated by ';': 'S0 S1: qx qy qz' on S0 <= s <= S1 "
                        "[m], 0 <= S0 < S1 <= L, force per unit arc length [N/m] in global axes, each component at "
                        "most 1e12 N/m in size. Body: 'ARM S0 S1: qx qy qz'. At most 1000.");
      prm.declare_entry("Node set forces", "", dealii::Patterns::Anything(),
                        "Solid: total forces on node sets, separated by ';': 'SET: Fx Fy Fz' [N], global axes, each "
                        "component at most 1e12 N in size. The force is spread as a uniform traction over the "
                        "boundary faces whose corners all belong to the set (consistent nodal weights), or in equal "
                        "shares over the set's nodes if it holds no whole face. At most 1000.");
      prm.declare_entry("Node forces", "", dealii::Patterns::Anything(),
                        "Solid: forces on every node of node sets, separated by ';': 'SET: Fx Fy Fz' [N] per node, "
                        "global axes, each component at most 1e12 N in size (as CalculiX's *CLOAD on a node set: the "
                        "total is the number of nodes times the force; with 'Element = hex8' only the corner nodes "
                        "carry it; for a traction use 'Node set forces'). At most 1000.");
      prm.declare_entry("Node set moments", "", dealii::Patterns::Anything(),
                        "Solid: moments on node sets, separated by ';': 'SET: Mx My Mz' [N m], global axes, about "
                        "the centroid of the set's boundary faces, each component at most 1e12 N m in size. Carried "
                        "by the traction t = lambda x r (r from the centroid), the smallest traction field with "
                        "that moment and no resultant force (a torque gives shear tractions growing with the "
                        "distance from the centroid, a bending moment a linear normal stress), consistent nodal "
                        "weights; a set without a whole face gets nodal forces lambda x r_i. At most 1000.");
      prm.declare_entry("Pressures", "", dealii::Patterns::Anything(),
                        "Solid: pressures on node sets, separated by ';': 'SET: p' [Pa], at most 1e12 Pa in size, on "
                        "the boundary faces whose corners all belong to the set: the traction -p n (n the outward "
                        "normal of the curved face), so p > 0 pushes on the faces; consistent nodal weights. At "
                        "most 1000.");
      prm.declare_entry("Support displacements", "", dealii::Patterns::Anything(),
                        "Prescribed displacements of supports (settlements), separated by ';'. Arm: 'S: ux uy uz' "
                        "[m] at the pinned or clamped support at arc length S [m], or 'S: ux uy uz theta_x theta_y "
                        "theta_z' [m, rad] at a clamped one. Solid: 'SUPPORT: ux uy uz' [m] with SUPPORT a node set "
                        "or plane of Solid/Supports, a value only in the components it fixes. Global axes, each "
                        "value at most 1e6 in size; supports not listed stay at zero. At most 1000.");
      prm.declare_entry("Gravity", "0, 0, 0", dealii::Patterns::Anything(),
                        "Acceleration of gravity 'gx, gy, gz' [m/s^2], each component at most 1e6 m/s^2 in size; "
                        "it loads the structure with its weight (density times volume).");
      prm.leave_subsection();
    }
}

LoadCase LoadCase::parse_parameters(ParameterHandler &prm, const std::string &name, const Arm *arm, const Solid *solid,
                                    const Body *body)
{
  LoadCase c;
  c.name = name;
  const std::string path = section_of(name) + "/";
  if (body && body->solid) solid = &*body->solid;
  prm.enter_subsection(section_of(name));
  const auto point_loads = [&](const std::string &entry_name, const std::string &what,
                               const geometry::NumberRange &range, std::vector<ArmPointLoad> &loads) {
    const std::string entry = path + entry_name;
    for (const auto &[where, value] : items(prm, entry_name, entry, body ? "ARM S: x y z' or 'POINT: x y z" : "S: x y z"))
      {
        ArmPointLoad load;
        static_cast<LoadPoint &>(load) = load_point(where, entry, what, arm, body);
        load.value = vector3(value, entry, what, range);
        loads.push_back(load);
      }
  };
  point_loads("Point forces", "point force", force_range, c.point_forces);
  point_loads("Point moments", "point moment", moment_range, c.point_moments);

  const std::string line_entry = path + "Line loads";
  for (const auto &[where, value] : items(prm, "Line loads", line_entry, body ? "ARM S0 S1: qx qy qz" : "S0 S1: qx qy qz"))
    {
      if (!arm && !body)
        throw InputError(line_entry, "the scene has no arm: line loads apply to 'Model = arm' and 'Model = body' scenes");
      auto w = base::words(where);
      ArmLineLoad l;
      if (body && w.size() == 3)
        {
          l.arm = body_arm(w[0], line_entry, *body);
          w.erase(w.begin());
        }
      else if (body)
        throw InputError(line_entry, "'" + base::printable_excerpt(where) + "' is not 'ARM S0 S1' (an arm of the body "
                                     "and an interval [m] on it)");
      if (w.size() != 2)
        throw InputError(line_entry, "'" + base::printable_excerpt(where) + "' is not an interval 'S0 S1' [m]");
      const Arm &on = arm ? *arm : body->arms[l.arm];
      l.s0 = arc_length(w[0], line_entry, "line load start", on);
      l.s1 = arc_length(w[1], line_entry, "line load end", on);
      if (!(l.s1 > l.s0))
        throw InputError(line_entry, "line load on '" + base::printable_excerpt(where) + "': allowed: S0 < S1");
      l.q = vector3(value, line_entry, "line load", line_load_range);
      c.line_loads.push_back(l);
    }
  const std::string set_entry = path + "Node set forces";
  for (const auto &[set, value] : items(prm, "Node set forces", set_entry, "SET: Fx Fy Fz"))
    c.node_set_forces.push_back({node_set(set, set_entry, solid), vector3(value, set_entry, "node set force", force_range)});
  const std::string node_entry = path + "Node forces";
  for (const auto &[set, value] : items(prm, "Node forces", node_entry, "SET: Fx Fy Fz"))
    c.node_forces.push_back({node_set(set, node_entry, solid), vector3(value, node_entry, "node force", force_range)});
  const std::string moment_entry = path + "Node set moments";
  for (const auto &[set, value] : items(prm, "Node set moments", moment_entry, "SET: Mx My Mz"))
    c.node_set_moments.push_back(
      {node_set(set, moment_entry, solid), vector3(value, moment_entry, "node set moment", moment_range)});
  const std::string pressure_entry = path + "Pressures";
  for (const auto &[set, value] : items(prm, "Pressures", pressure_entry, "SET: p"))
    c.pressures.push_back({node_set(set, pressure_entry, solid),
                           geometry::checked_number(base::parse_number(value, pressure_entry, "a pressure [Pa]"),
                                                    pressure_entry, pressure_range)});
  const std::string support_entry = path + "Support displacements";
  for (const auto &[where, value] : items(prm, "Support displacements", support_entry, arm ? "S: ux uy uz" : "SUPPORT: ux uy uz"))
    {
      if (arm)
        c.support_displacements.push_back(arm_support_displacement(where, value, support_entry, *arm));
      else if (solid && !body)
        c.support_displacements.push_back(solid_support_displacement(where, value, support_entry, *solid));
      else
        throw InputError(support_entry, "support displacements apply to 'Model = arm' and 'Model = solid' scenes; a "
                                        "body is held at its interfaces");
    }
  const auto g = base::parse_vector3(prm.get("Gravity"), path + "Gravity", "m/s^2");
  for (unsigned int d = 0; d < 3; ++d) c.gravity[d] = geometry::checked_number(g[d], path + "Gravity", gravity_range);
  prm.leave_subsection();
  return c;
}

Resultant LoadCase::resultant_on(const Arm &arm) const
{
  Resultant r;
  const auto &curve = *arm.curve;
  for (const auto &p : point_forces)
    {
      r.force += p.value;
      r.moment += cross_product_3d(Tensor<1, 3>(curve.position(p.s)), p.value);
    }
  for (const auto &p : point_moments) r.moment += p.value;
  const auto distributed = [&](const double a, const double b, const Tensor<1, 3> &q) {
    integrate(a, b, [&](const double s, const double ds) {
      r.force += q * ds;
      r.moment += cross_product_3d(Tensor<1, 3>(curve.position(s)), q) * ds;
    });
  };
  for (const auto &l : line_loads) distributed(l.s0, l.s1, l.q);
  if (gravity.norm() > 0) distributed(0, curve.length(), arm.material.density * arm.section.area * gravity);
  return r;
}

Arm with_load_stations(const Arm &arm, const std::vector<LoadCase> &cases, const std::vector<double> &points)
{
  Arm result = arm;
  auto station = [&](const double s) { result.supports.push_back({s, SupportKind::free}); };
  for (const double s : points) station(s);
  for (const auto &c : cases)
    {
      for (const auto &p : c.point_forces) station(p.s);
      for (const auto &p : c.point_moments) station(p.s);
      for (const auto &l : c.line_loads)
        {
          station(l.s0);
          station(l.s1);
        }
    }
  return result;
}

void StaticSettings::declare_load_case_list(ParameterHandler &prm)
{
  prm.enter_subsection("Static");
  prm.declare_entry("Load cases", "", dealii::Patterns::Anything(),
                    "Names of the load cases of 'flextrack static', separated by commas (letters, digits, '_'); "
                    "each case NAME is described in its own 'subsection Load case NAME'. At most 1000.");
  prm.leave_subsection();
}

std::vector<std::string> StaticSettings::parse_load_case_list(ParameterHandler &prm)
{
  prm.enter_subsection("Static");
  const std::string text = prm.get("Load cases");
  prm.leave_subsection();
  auto names = base::parse_name_list(text, "Static/Load cases", "load case name");
  if (names.size() > max_load_cases)
    throw InputError("Static/Load cases", std::to_string(names.size()) + " load cases; at most " +
                                            std::to_string(max_load_cases) + " are allowed");
  return names;
}

void StaticSettings::declare_parameters(ParameterHandler &prm)
{
  declare_load_case_list(prm);
  prm.enter_subsection("Static");
  prm.declare_entry("Points", "", dealii::Patterns::Anything(),
                    "Arm: arc lengths S [m], 0 <= S <= L, separated by commas, where 'flextrack static' reports "
                    "the displacement and rotation (a mesh node is placed at each); empty: the end of the arm "
                    "(s = L). Body: places 'ARM S' (an arm of the body, S [m] on it) or names of interfaces and "
                    "output points, separated by commas, where the full and the reduced body's displacements are "
                    "compared; empty: every interface, output point and point load. At most 1000.");
  prm.declare_entry("Linear solver", "auto", dealii::Patterns::Selection("auto|direct|iterative"),
                    "How K u = f is solved: 'direct' = sparse Cholesky factor (CHOLMOD), exact to round-off, one "
                    "factor for all load cases; 'iterative' (solid scenes) = conjugate gradients with a "
                    "smoothed-aggregation algebraic multigrid preconditioner (Trilinos ML, the rigid motions as "
                    "its near-null space): a fraction of the factor's memory on large solids, each load case its "
                    "own iteration, accurate to 'Solver tolerance'; 'auto' = iterative for solids of more than "
                    "100000 degrees of freedom (where the factor needs gigabytes), direct otherwise.");
  prm.declare_entry("Solver tolerance", "1e-10", dealii::Patterns::Double(),
                    "Iterative solver: each conjugate-gradient solve stops when the residual's 2-norm is this "
                    "fraction of the load's [-], 1e-12 to 1e-8 (the residual of a double-precision K u stalls "
                    "near 1e-12; coarser would pass unbalanced solutions as equilibrium).");
  prm.declare_entry("Node sets", "", dealii::Patterns::Anything(),
                    "Solid: node sets whose mean displacement [m] 'flextrack static' reports, separated by commas; "
                    "empty: the node sets that carry forces. At most 1000.");
  prm.leave_subsection();
}

StaticSettings StaticSettings::parse_parameters(ParameterHandler &prm, const Arm *arm, const Solid *solid,
                                                const Body *body)
{
  StaticSettings s;
  s.load_cases = parse_load_case_list(prm);
  if (body && body->solid) solid = &*body->solid;
  prm.enter_subsection("Static");
  const auto points = base::split(prm.get("Points"), ',');
  const auto sets = base::words(prm.get("Node sets"));
  s.solver = prm.get("Linear solver");
  s.tolerance = geometry::checked_number(prm.get_double("Solver tolerance"), "Static/Solver tolerance",
                                         {1e-12, 1e-8, true, "-"});
  prm.leave_subsection();
  if (sets.size() > max_load_items)
    throw InputError("Static/Node sets", std::to_string(sets.size()) + " node sets; at most " +
                                          std::to_string(max_load_items) + " are allowed");
  for (const auto &set : sets) s.node_sets.push_back(node_set(set, "Static/Node sets", solid));
  const std::string entry = "Static/Points";
  if (points.size() > max_load_items)
    throw InputError(entry, std::to_string(points.size()) + " points; at most " + std::to_string(max_load_items) +
                              " are allowed");
  if (!points.empty() && !arm && !body)
    throw InputError(entry, "the scene has no arm: report points at arc lengths apply to 'Model = arm' and "
                            "'Model = body' scenes");
  for (const auto &p : points)
    {
      const auto place = load_point(p, entry, "report point", arm, body);
      if (arm)
        s.points.push_back(place.s);
      else
        s.body_points.push_back(place);
    }
  return s;
}
} // namespace flextrack::fem
