// Helpers for the multibody tests: joints built through the joint table's parameters (so the
// tests also exercise what a scene reader calls), rigid bodies, and a run to t_end.
#pragma once

#include <multibody/body.h>
#include <multibody/ida_integrator.h>
#include <multibody/initial_conditions.h>
#include <multibody/joint_table.h>
#include <multibody/system.h>

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <sstream>
#include <string>

namespace flextrack::multibody::test
{
inline std::string vec(const Vector3 &v)
{
  std::ostringstream s;
  s.precision(17);
  s << v[0] << ", " << v[1] << ", " << v[2];
  return s.str();
}

/// A joint of @p kind between @p body1 and @p body2 at @p position with z axis @p axis.
inline void add_joint(System &system, const std::string &kind, const std::string &name, const std::string &body1,
                      const std::string &body2, const Vector3 &position, const Vector3 &axis,
                      const std::string &driver = "", const Vector3 &reference = Vector3({1, 0, 0}))
{
  dealii::ParameterHandler prm;
  declare_joint_parameters(prm);
  prm.set("Kind", kind);
  prm.set("Body 1", body1);
  prm.set("Body 2", body2);
  prm.set("Position", vec(position));
  prm.set("Axis", vec(axis));
  prm.set("Reference axis", vec(reference));
  prm.set("Driver", driver);
  system.add_joint(create_joint(name, prm, system.body_lookup()));
}

inline const Body &add_rigid(System &system, const std::string &name, const double mass, const Matrix3 &inertia,
                             const Vector3 &position, const geometry::EulerParameters &p = {{1, 0, 0, 0}},
                             const Vector3 &velocity = Vector3(), const Vector3 &angular_velocity = Vector3(),
                             const Vector3 &centre_of_mass = Vector3())
{
  RigidProperties r;
  r.mass = mass;
  r.inertia_centre_of_mass = inertia;
  r.centre_of_mass = centre_of_mass;
  InitialState s;
  s.position = position;
  s.orientation = p;
  s.velocity = velocity;
  s.angular_velocity = angular_velocity;
  return system.add_body(std::make_unique<FloatingBody>(name, r, s));
}

inline Matrix3 diagonal(const double a, const double b, const double c)
{
  Matrix3 J;
  J[0][0] = a;
  J[1][1] = b;
  J[2][2] = c;
  return J;
}

inline IntegratorSettings tight(const double rtol = 1e-10, const double atol = 1e-12)
{
  IntegratorSettings s;
  s.relative_tolerance = rtol;
  s.absolute_tolerance = atol;
  return s;
}
} // namespace flextrack::multibody::test
