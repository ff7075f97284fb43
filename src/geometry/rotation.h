// The rotation toolbox: cross-product matrices and Euler parameters (unit quaternions), used by
// the FE stage (rigid ties), the reduction (inertia invariants) and the multibody stage.
// Conventions (doc/formulation.md): A maps body axes to global axes, x_global = R + A x_body;
// Euler parameters p = (p0, p1, p2, p3) with |p| = 1, p0 = cos(phi/2), (p1, p2, p3) = sin(phi/2) n.
// With G = [-e, -e~ + p0 1] (3 x 4, e = (p1, p2, p3)) the body angular velocity is
// omega = 2 G p' and p' = G^T omega / 2 (Nikravesh, Computer-Aided Analysis of Mechanical Systems,
// 1988, ch. 6).
#pragma once

#include <deal.II/base/tensor.h>

#include <array>
#include <cmath>

namespace flextrack::geometry
{
using Vector3 = dealii::Tensor<1, 3>;
using Matrix3 = dealii::Tensor<2, 3>;
using EulerParameters = std::array<double, 4>;

/// The cross-product matrix v~ with v~ w = v x w.
inline Matrix3 skew(const Vector3 &v)
{
  Matrix3 S;
  S[0][1] = -v[2];
  S[0][2] = v[1];
  S[1][0] = v[2];
  S[1][2] = -v[0];
  S[2][0] = -v[1];
  S[2][1] = v[0];
  return S;
}

/// The axial vector of the skew part of @p M: v with v~ = (M - M^T) / 2.
inline Vector3 axial(const Matrix3 &M)
{
  return Vector3({0.5 * (M[2][1] - M[1][2]), 0.5 * (M[0][2] - M[2][0]), 0.5 * (M[1][0] - M[0][1])});
}

/// Levi-Civita symbol e_abc.
inline double levi_civita(const unsigned int a, const unsigned int b, const unsigned int c)
{
  return 0.5 * (double(a) - double(b)) * (double(b) - double(c)) * (double(c) - double(a));
}

/// The rotation matrix A(p) of Euler parameters @p p (need not be normalised exactly: A is
/// computed for p / |p|, so that a slightly drifted p still gives an orthogonal A).
inline Matrix3 rotation_matrix(const EulerParameters &p)
{
  const double n2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3];
  const double s = 2.0 / n2;
  const double e0 = p[0], e1 = p[1], e2 = p[2], e3 = p[3];
  Matrix3 A;
  A[0][0] = 1 - s * (e2 * e2 + e3 * e3);
  A[0][1] = s * (e1 * e2 - e0 * e3);
  A[0][2] = s * (e1 * e3 + e0 * e2);
  A[1][0] = s * (e1 * e2 + e0 * e3);
  A[1][1] = 1 - s * (e1 * e1 + e3 * e3);
  A[1][2] = s * (e2 * e3 - e0 * e1);
  A[2][0] = s * (e1 * e3 - e0 * e2);
  A[2][1] = s * (e2 * e3 + e0 * e1);
  A[2][2] = 1 - s * (e1 * e1 + e2 * e2);
  return A;
}

/// Euler parameters of a rotation by @p angle [rad] about @p axis (any length > 0).
inline EulerParameters euler_parameters_from_axis_angle(const Vector3 &axis, const double angle)
{
  const Vector3 n = axis / axis.norm();
  const double s = std::sin(0.5 * angle);
  return {{std::cos(0.5 * angle), s * n[0], s * n[1], s * n[2]}};
}

/// Euler parameters of the rotation vector @p phi (axis phi / |phi|, angle |phi| [rad]).
inline EulerParameters euler_parameters_from_rotation_vector(const Vector3 &phi)
{
  const double angle = phi.norm();
  if (angle == 0) return {{1, 0, 0, 0}};
  return euler_parameters_from_axis_angle(phi, angle);
}

/// Euler parameters of an orthogonal matrix @p A (Shepperd's method: the largest of the four
/// squared parameters is computed first, so no division by a small number).
inline EulerParameters euler_parameters_from_matrix(const Matrix3 &A)
{
  const double t = A[0][0] + A[1][1] + A[2][2];
  const double d[4] = {t, A[0][0], A[1][1], A[2][2]};
  unsigned int i = 0;
  for (unsigned int k = 1; k < 4; ++k)
    if (d[k] > d[i]) i = k;
  EulerParameters p;
  if (i == 0)
    {
      const double p0 = 0.5 * std::sqrt(1 + t);
      p = {{p0, (A[2][1] - A[1][2]) / (4 * p0), (A[0][2] - A[2][0]) / (4 * p0), (A[1][0] - A[0][1]) / (4 * p0)}};
    }
  else
    {
      const unsigned int a = i - 1, b = (a + 1) % 3, c = (a + 2) % 3;
      const double pa = 0.5 * std::sqrt(1 + 2 * A[a][a] - t);
      p[0] = (A[c][b] - A[b][c]) / (4 * pa);
      p[1 + a] = pa;
      p[1 + b] = (A[b][a] + A[a][b]) / (4 * pa);
      p[1 + c] = (A[c][a] + A[a][c]) / (4 * pa);
    }
  if (p[0] < 0)
    for (auto &x : p) x = -x;
  return p;
}

/// G(p) (3 x 4): body angular velocity omega = 2 G p'.  G = [-e, -e~ + p0 1].
inline std::array<std::array<double, 4>, 3> body_velocity_matrix(const EulerParameters &p)
{
  return {{{{-p[1], p[0], p[3], -p[2]}}, {{-p[2], -p[3], p[0], p[1]}}, {{-p[3], p[2], -p[1], p[0]}}}};
}
} // namespace flextrack::geometry
