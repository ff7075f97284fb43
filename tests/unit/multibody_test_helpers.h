// Helpers for the multibody tests: joints built through the joint table's parameters (so the
// tests also exercise what a scene reader calls), rigid bodies, and a run to t_end.
#pragma once

#include <geometry/rotation.h>
#include <multibody/body.h>
#include <multibody/ida_integrator.h>
#include <multibody/initial_conditions.h>
#include <multibody/joint_table.h>
#include <multibody/system.h>

#include <deal.II/base/parameter_handler.h>

#include <Epetra_CrsMatrix.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

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

/// The compound pendulum of issue 9's test, added to @p s (gravity -9.81 m/s^2 along y): m =
/// 1.5 kg, centre of mass at L = 0.8 m from the pivot, J_c = 0.02 kg m^2, a revolute joint 'pivot'
/// about z at the origin, released at rest from 150 deg. Returns its period [s] in closed form:
/// theta'' = -(m g L / I_p) sin theta with I_p = m L^2 + J_c gives 4 sqrt(I_p / (m g L))
/// K(sin(theta0 / 2)), K(k) = pi / (2 agm(1, sqrt(1 - k^2))) by the arithmetic-geometric mean.
inline double add_large_amplitude_pendulum(System &s)
{
  const double m = 1.5, L = 0.8, Jc = 0.02, g = 9.81, theta0 = 150 * M_PI / 180;
  add_rigid(s, "bob", m, diagonal(Jc, Jc, Jc), Vector3({L * std::sin(theta0), -L * std::cos(theta0), 0}),
            geometry::euler_parameters_from_axis_angle(Vector3({0, 0, 1}), theta0));
  add_joint(s, "revolute", "pivot", "bob", "ground", Vector3(), Vector3({0, 0, 1}));
  const double k = std::sin(theta0 / 2);
  double a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 60 && std::abs(a - b) > 1e-16 * a; ++i)
    {
      const double mean = 0.5 * (a + b);
      b = std::sqrt(a * b);
      a = mean;
    }
  const double K = M_PI / (a + b); // pi / (2 agm)
  return 4 * std::sqrt((m * L * L + Jc) / (m * g * L)) * K;
}

inline IntegratorSettings tight(const double rtol = 1e-10, const double atol = 1e-12)
{
  IntegratorSettings s;
  s.relative_tolerance = rtol;
  s.absolute_tolerance = atol;
  return s;
}

/// A planar four-bar under gravity (-9.81 m/s^2 along y), finalised: ground pivots A = (0,0,0) and
/// D = (2,0,0), crank AB = 1 m up (B = (0,1,0)), coupler BC = 2.5 m, rocker CD = 2 m (C the upper
/// intersection), four revolute joints about z named A, B, C, D; the crank started at 1 rad/s.
/// 20 equations for 18 coordinates and one degree of freedom: 3 are dependent everywhere.
inline void add_planar_four_bar(System &s)
{
  const Vector3 A, B({0, 1, 0}), D({2, 0, 0});
  const double b = 2.5, c = 2.0, d = (D - B).norm(), a_ = (b * b - c * c + d * d) / (2 * d), h = std::sqrt(b * b - a_ * a_);
  const Vector3 e = (D - B) / d, n({-e[1], e[0], 0});
  const Vector3 C = B + a_ * e + h * n;
  add_rigid(s, "crank", 1.0, diagonal(0.01, 0.1, 0.1), 0.5 * (A + B),
            geometry::euler_parameters_from_axis_angle(Vector3({0, 0, 1}), M_PI / 2), Vector3(), Vector3({0, 0, 1}));
  add_rigid(s, "coupler", 2.0, diagonal(0.01, 1.0, 1.0), 0.5 * (B + C));
  add_rigid(s, "rocker", 1.5, diagonal(0.01, 0.5, 0.5), 0.5 * (C + D));
  add_joint(s, "revolute", "A", "crank", "ground", A, Vector3({0, 0, 1}));
  add_joint(s, "revolute", "B", "coupler", "crank", B, Vector3({0, 0, 1}));
  add_joint(s, "revolute", "C", "rocker", "coupler", C, Vector3({0, 0, 1}));
  add_joint(s, "revolute", "D", "rocker", "ground", D, Vector3({0, 0, 1}));
  s.finalize();
}
/// Entry (row, col) of an assembled matrix (0 where it holds none).
inline double matrix_entry(const Epetra_CrsMatrix &A, const int row, const int col)
{
  int n = 0;
  std::vector<double> values(A.NumGlobalCols());
  std::vector<int> cols(A.NumGlobalCols());
  A.ExtractGlobalRowCopy(row, values.size(), n, values.data(), cols.data());
  for (int k = 0; k < n; ++k)
    if (cols[k] == col) return values[k];
  return 0;
}
} // namespace flextrack::multibody::test
