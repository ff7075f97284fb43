// Parameters of the force kinds (`subsection Force NAME`), and the kind table.
#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>
#include <multibody/force.h>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
const Body &body_entry(ParameterHandler &prm, const std::string &entry, const std::string &prefix, const BodyLookup &bodies)
{
  const std::string name = base::trim(prm.get(entry));
  const Body *b = base::is_valid_name(name) ? bodies(name) : nullptr;
  if (!b) throw InputError(prefix + entry, "there is no body '" + base::printable_excerpt(name) + "'");
  return *b;
}

Vector3 vector_entry(ParameterHandler &prm, const std::string &entry, const std::string &prefix, const std::string &unit)
{
  const auto v = base::parse_vector3(prm.get(entry), prefix + entry, unit);
  return Vector3({v[0], v[1], v[2]});
}

/// A marker at a global point with global axes (z = Axis) on @p body at its initial pose.
std::unique_ptr<Marker> marker_entry(ParameterHandler &prm, const Body &body, const std::string &position_entry,
                                     const std::string &prefix, const std::string &name)
{
  const Vector3 position = vector_entry(prm, position_entry, prefix, "m");
  Vector3 z = vector_entry(prm, "Axis", prefix, "-");
  if (z.norm() == 0) throw InputError(prefix + "Axis", "must not be zero");
  z /= z.norm();
  const Vector3 trial = std::abs(z[0]) < 0.9 ? Vector3({1, 0, 0}) : Vector3({0, 1, 0});
  Vector3 x = trial - (trial * z) * z;
  x /= x.norm();
  const Vector3 y = cross_product_3d(z, x);
  Matrix3 axes;
  for (unsigned int a = 0; a < 3; ++a) axes[a][0] = x[a], axes[a][1] = y[a], axes[a][2] = z[a];
  std::vector<double> q(body.n_q()), v(body.n_v());
  body.initial_coordinates(q.data(), v.data());
  return FixedMarker::at_global_pose(body, name, position, axes, q.data());
}

std::array<geometry::Expression, 3> expressions(ParameterHandler &prm, const std::string &entry, const std::string &prefix,
                                                const geometry::TimeWindow &window)
{
  const auto items = base::split(prm.get(entry), ';');
  if (items.size() != 3) throw InputError(prefix + entry, "needs three expressions of t separated by ';'");
  try
    {
      std::array<geometry::Expression, 3> laws{{geometry::Expression(items[0], "t"), geometry::Expression(items[1], "t"),
                                                geometry::Expression(items[2], "t")}};
      for (const auto &law : laws) geometry::check_time_law(law, window, 0);
      return laws;
    }
  catch (const geometry::ExpressionError &e)
    {
      throw InputError(prefix + entry, e.what());
    }
}
} // namespace

void declare_force_parameters(ParameterHandler &prm)
{
  prm.declare_entry("Kind", "applied load", Patterns::Selection("applied load|spring damper|rotational spring damper"),
                    "Kind of force [-]: applied load (on body 1), spring damper (between the points of body 1 "
                    "and body 2), rotational spring damper (about Axis, between body 1 and body 2).");
  prm.declare_entry("Body 1", "", Patterns::Anything(), "Body the load acts on / first body [-].");
  prm.declare_entry("Body 2", "ground", Patterns::Anything(), "Second body of a spring damper [-].");
  prm.declare_entry("Position 1", "0, 0, 0", Patterns::Anything(), "Point of body 1, global, at the initial configuration [m].");
  prm.declare_entry("Position 2", "0, 0, 0", Patterns::Anything(), "Point of body 2, global, at the initial configuration [m].");
  prm.declare_entry("Axis", "0, 0, 1", Patterns::Anything(), "Axis of a rotational spring damper (z of the markers), global [-].");
  prm.declare_entry("Force", "0; 0; 0", Patterns::Anything(), "Applied force components as expressions of t [N].");
  prm.declare_entry("Torque", "0; 0; 0", Patterns::Anything(), "Applied torque components as expressions of t [N m].");
  prm.declare_entry("Body axes", "false", Patterns::Bool(),
                    "Applied load components in the axes of the marker on body 1 (true) or global (false) [-].");
  prm.declare_entry("Stiffness", "0", Patterns::Double(0), "Spring stiffness [N/m] or [N m/rad].");
  prm.declare_entry("Damping", "0", Patterns::Double(0), "Damper coefficient [N s/m] or [N m s/rad].");
  prm.declare_entry("Free length", "-1", Patterns::Double(), "Spring free length [m]; negative: the initial length.");
  prm.declare_entry("Free angle", "0", Patterns::Double(), "Rotational spring free angle [rad] (0: the initial configuration).");
}

std::unique_ptr<Force> create_force(const std::string &name, ParameterHandler &prm, const BodyLookup &bodies,
                                    const geometry::TimeWindow &window)
{
  const std::string prefix = "Force " + name + "/";
  if (!base::is_valid_name(name)) throw InputError("Force " + base::printable_excerpt(name), "is not a valid force name (" + base::name_rule() + ")");
  const std::string kind = prm.get("Kind");
  const Body &b1 = body_entry(prm, "Body 1", prefix, bodies);
  auto m1 = marker_entry(prm, b1, "Position 1", prefix, name + "_1");
  if (kind == "applied load")
    return std::make_unique<AppliedLoad>(name, std::move(m1), expressions(prm, "Force", prefix, window),
                                         expressions(prm, "Torque", prefix, window), prm.get_bool("Body axes"));
  const Body &b2 = body_entry(prm, "Body 2", prefix, bodies);
  const std::string p2 = kind == "spring damper" ? "Position 2" : "Position 1"; // coaxial markers for the rotational one
  auto m2 = marker_entry(prm, b2, p2, prefix, name + "_2");
  const double k = prm.get_double("Stiffness"), c = prm.get_double("Damping");
  if (kind == "spring damper")
    {
      const double distance =
        (vector_entry(prm, "Position 1", prefix, "m") - vector_entry(prm, "Position 2", prefix, "m")).norm();
      // The force acts along the line between the points: at coincident points it has no direction.
      if (!(distance > 1e-9))
        throw InputError(prefix + "Position 2", "is " + std::to_string(distance) + " m from Position 1: a spring damper "
                                                "acts along the line between its two points, which must be apart at the "
                                                "start (more than 1e-9 m); use a joint to hold two points together");
      double L0 = prm.get_double("Free length");
      if (L0 < 0) L0 = distance;
      return std::make_unique<SpringDamper>(name, std::move(m1), std::move(m2), k, c, L0);
    }
  return std::make_unique<RotationalSpringDamper>(name, std::move(m1), std::move(m2), k, c, prm.get_double("Free angle"));
}
} // namespace flextrack::multibody
