// The joint table and the parameters of mask joints.
#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>
#include <multibody/generic_joint.h>
#include <multibody/joint_table.h>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
Vector3 vector_entry(ParameterHandler &prm, const std::string &entry, const std::string &prefix, const std::string &unit)
{
  const auto v = base::parse_vector3(prm.get(entry), prefix + entry, unit);
  return Vector3({v[0], v[1], v[2]});
}

const Body &body_entry(ParameterHandler &prm, const std::string &entry, const std::string &prefix, const BodyLookup &bodies)
{
  const std::string name = base::trim(prm.get(entry));
  if (!base::is_valid_name(name)) throw InputError(prefix + entry, "'" + base::printable_excerpt(name) + "' is not a valid body name (" + base::name_rule() + ")");
  const Body *b = bodies(name);
  if (!b) throw InputError(prefix + entry, "there is no body '" + name + "'");
  return *b;
}

/// Global joint axes (columns x, y, z) from the z axis and an optional x reference.
Matrix3 joint_axes(const Vector3 &axis, const Vector3 &reference, const std::string &prefix)
{
  if (axis.norm() == 0) throw InputError(prefix + "Axis", "must not be zero");
  const Vector3 z = axis / axis.norm();
  Vector3 x = reference - (reference * z) * z;
  if (x.norm() < 1e-8) // no usable reference: any perpendicular
    {
      const Vector3 trial = std::abs(z[0]) < 0.9 ? Vector3({1, 0, 0}) : Vector3({0, 1, 0});
      x = trial - (trial * z) * z;
    }
  x /= x.norm();
  const Vector3 y = cross_product_3d(z, x);
  Matrix3 A;
  for (unsigned int a = 0; a < 3; ++a)
    {
      A[a][0] = x[a];
      A[a][1] = y[a];
      A[a][2] = z[a];
    }
  return A;
}

std::unique_ptr<Joint> make_mask_joint(const std::string &name, ParameterHandler &prm, const BodyLookup &bodies,
                                       const JointMask &mask, const DriverKind drivable)
{
  const std::string prefix = "Joint " + name + "/";
  const Body &b1 = body_entry(prm, "Body 1", prefix, bodies), &b2 = body_entry(prm, "Body 2", prefix, bodies);
  if (&b1 == &b2) throw InputError(prefix + "Body 2", "joins body '" + b1.name() + "' to itself");
  const Vector3 position = vector_entry(prm, "Position", prefix, "m");
  const Matrix3 axes = joint_axes(vector_entry(prm, "Axis", prefix, "-"), vector_entry(prm, "Reference axis", prefix, "-"), prefix);

  std::unique_ptr<Marker> m[2];
  const Body *b[2] = {&b1, &b2};
  for (unsigned int i = 0; i < 2; ++i)
    {
      std::vector<double> q(b[i]->n_q()), v(b[i]->n_v());
      b[i]->initial_coordinates(q.data(), v.data());
      try
        {
          m[i] = FixedMarker::at_global_pose(*b[i], name + "_" + std::to_string(i + 1), position, axes, q.data(),
                                             base::trim(prm.get("Interface " + std::to_string(i + 1))));
        }
      catch (const InputError &e)
        {
          throw InputError(prefix + "Interface " + std::to_string(i + 1), e.message());
        }
    }

  const std::string law_text = base::trim(prm.get("Driver"));
  DriverKind driver = DriverKind::none;
  std::shared_ptr<const geometry::Expression> law;
  if (!law_text.empty())
    {
      if (drivable == DriverKind::none) throw InputError(prefix + "Driver", "this joint kind cannot be driven (revolute: angle, prismatic: displacement)");
      try
        {
          law = std::make_shared<geometry::Expression>(law_text, "t");
        }
      catch (const geometry::ExpressionError &e)
        {
          throw InputError(prefix + "Driver", e.what());
        }
      driver = drivable;
    }
  return std::make_unique<GenericJoint>(name, std::move(m[0]), std::move(m[1]), mask, driver, law);
}

JointKind mask_kind(const std::string &name, const std::string &doc, const JointMask mask,
                    const DriverKind drivable = DriverKind::none)
{
  return {name, doc, [mask, drivable](const std::string &n, ParameterHandler &prm, const BodyLookup &b) {
            return make_mask_joint(n, prm, b, mask, drivable);
          }};
}
} // namespace

const std::vector<JointKind> &joint_kinds()
{
  using M = JointMask;
  static const std::vector<JointKind> kinds = {
    mask_kind("fixed", "all six relative motions locked", M{{{true, true, true}}, {{true, true, true}}}),
    mask_kind("revolute", "rotation about z free; Driver: angle [rad]", M{{{true, true, true}}, {{true, true, false}}},
              DriverKind::angle),
    mask_kind("spherical", "all rotations free", M{{{true, true, true}}, {{false, false, false}}}),
    mask_kind("prismatic", "translation along z free; Driver: displacement [m]",
              M{{{true, true, false}}, {{true, true, true}}}, DriverKind::displacement),
    mask_kind("cylindrical", "translation along and rotation about z free", M{{{true, true, false}}, {{true, true, false}}}),
    mask_kind("universal", "rotations about x of body 1 and y of body 2 free (cross of pins)",
              M{{{true, true, true}}, {{false, false, true}}}),
    mask_kind("planar", "translations along x, y and rotation about z free", M{{{false, false, true}}, {{true, true, false}}}),
    mask_kind("point_in_plane", "the point of body 1 stays in the x-y plane of body 2",
              M{{{false, false, true}}, {{false, false, false}}}),
  };
  return kinds;
}

std::string joint_kind_names()
{
  std::string s;
  for (const auto &k : joint_kinds()) s += (s.empty() ? "" : ", ") + k.name;
  return s;
}

void declare_joint_parameters(ParameterHandler &prm)
{
  std::string selection;
  for (const auto &k : joint_kinds()) selection += (selection.empty() ? "" : "|") + k.name;
  prm.declare_entry("Kind", "revolute", Patterns::Selection(selection), "Kind of joint [-]: " + joint_kind_names() + ".");
  prm.declare_entry("Body 1", "", Patterns::Anything(), "Name of the first body (the follower) [-].");
  prm.declare_entry("Body 2", "ground", Patterns::Anything(), "Name of the second body (the base, whose marker axes are the joint axes) [-].");
  prm.declare_entry("Position", "0, 0, 0", Patterns::Anything(), "Joint origin, global, at the initial configuration [m].");
  prm.declare_entry("Axis", "0, 0, 1", Patterns::Anything(), "Joint z axis, global, at the initial configuration [-].");
  prm.declare_entry("Reference axis", "1, 0, 0", Patterns::Anything(),
                    "Joint x axis (made perpendicular to z), global, at the initial configuration [-].");
  prm.declare_entry("Interface 1", "", Patterns::Anything(),
                    "Interface of body 1 (flexible) the joint attaches to; empty: the joint position [-].");
  prm.declare_entry("Interface 2", "", Patterns::Anything(), "Interface of body 2 (flexible); empty: the joint position [-].");
  prm.declare_entry("Driver", "", Patterns::Anything(),
                    "Prescribed motion as an expression of t [s]: revolute angle about z [rad], prismatic "
                    "displacement along z [m], from the initial configuration; empty: free.");
}

std::unique_ptr<Joint> create_joint(const std::string &name, ParameterHandler &prm, const BodyLookup &bodies)
{
  if (!base::is_valid_name(name)) throw InputError("Joint " + base::printable_excerpt(name), "is not a valid joint name (" + base::name_rule() + ")");
  const std::string kind = prm.get("Kind");
  for (const auto &k : joint_kinds())
    if (k.name == kind) return k.create(name, prm, bodies);
  throw InputError("Joint " + name + "/Kind", "unknown joint kind '" + kind + "'; allowed: " + joint_kind_names());
}
} // namespace flextrack::multibody
