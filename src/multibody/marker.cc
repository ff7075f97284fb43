// Kinematics of a marker fixed on a (possibly flexible) body; see marker.h for the formulas.
#include <base/input_error.h>
#include <multibody/marker.h>

namespace flextrack::multibody
{
using namespace dealii;
using geometry::skew;

FixedMarker::FixedMarker(const Body &body, std::string name, const Point<3> &point, const Matrix3 &frame,
                         const FullMatrix<double> &modes)
  : Marker(body, std::move(name)), x0(point), a0(frame), phi(modes)
{
  if (phi.m() == 0) phi.reinit(6, body.n_modes());
  Assert(phi.n() == body.n_modes(), ExcMessage("interface modes do not match the body's modes"));
  // z = x0 + Phi_u eta for the position; b_c = a0_c + theta x a0_c = a0_c - a0_c~ Phi_th eta
  // for axis c (as evaluate() below).
  const unsigned int n = phi.n();
  form.z0[0] = Vector3(x0);
  form.Z[0].reinit(3, n);
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int m = 0; m < n; ++m) form.Z[0](a, m) = phi(a, m);
  for (unsigned int c = 0; c < 3; ++c)
    {
      for (unsigned int b = 0; b < 3; ++b) form.z0[1 + c][b] = a0[b][c];
      const Matrix3 a_skew = skew(form.z0[1 + c]);
      form.Z[1 + c].reinit(3, n);
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int m = 0; m < n; ++m)
          for (unsigned int b = 0; b < 3; ++b) form.Z[1 + c](a, m) -= a_skew[a][b] * phi(3 + b, m);
    }
  form.Z_rotation.reinit(3, n);
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int m = 0; m < n; ++m) form.Z_rotation(a, m) = phi(3 + a, m);
}

void BodyFixedDerivatives::reinit(const BodyFixedForm &form, const Body &body, const double *q, const double *v,
                                  const MarkerKinematics &k)
{
  f = &form;
  n = body.n_modes();
  const unsigned int nq = body.n_q();
  const geometry::EulerParameters p{{q[3], q[4], q[5], q[6]}};
  A = geometry::rotation_matrix(p);
  c = 2 / (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3]);
  G = geometry::body_velocity_matrix(p);
  const Vector3 omega({v[3], v[4], v[5]});
  const Matrix3 A_omega = A * skew(omega);
  // -c A s~ G into the p columns of V
  const auto p_columns = [&](const Vector3 &s, FullMatrix<double> &V) {
    const Matrix3 As = A * skew(s);
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int e = 0; e < 4; ++e) V(i, 3 + e) = -c * (As[i][0] * G[0][e] + As[i][1] * G[1][e] + As[i][2] * G[2][e]);
  };
  for (unsigned int a = 0; a < 4; ++a)
    {
      const FullMatrix<double> &Z = form.Z[a];
      const FullMatrix<double> &J = a == 0 ? k.J_position : k.J_axes[a - 1];
      z[a] = form.z0[a];
      Vector3 Z_etadot;
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < n; ++j) z[a][i] += Z(i, j) * q[7 + j], Z_etadot[i] += Z(i, j) * v[6 + j];
      y[a].reinit(3, nq);
      velocity[a].reinit(3, nq);
      p_columns(cross_product_3d(omega, z[a]) + Z_etadot, velocity[a]);
      for (unsigned int i = 0; i < 3; ++i)
        {
          if (a == 0) y[a](i, i) = 1;
          for (unsigned int e = 0; e < 4; ++e) y[a](i, 3 + e) = c * (J(i, 3) * G[0][e] + J(i, 4) * G[1][e] + J(i, 5) * G[2][e]);
          for (unsigned int j = 0; j < n; ++j)
            {
              y[a](i, 7 + j) = J(i, 6 + j);
              velocity[a](i, 7 + j) = A_omega[i][0] * Z(0, j) + A_omega[i][1] * Z(1, j) + A_omega[i][2] * Z(2, j);
            }
        }
    }
  Vector3 s = omega; // omega + Phi_th eta'
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < n; ++j) s[i] += form.Z_rotation(i, j) * v[6 + j];
  velocity[4].reinit(3, nq);
  p_columns(s, velocity[4]);
}

void BodyFixedDerivatives::add_H(const unsigned int a, const Vector3 &w, FullMatrix<double> &D, const unsigned int row0,
                                 const unsigned int col0) const
{
  const Matrix3 b_skew = skew(transpose(A) * w);
  const FullMatrix<double> &Z = a < 4 ? f->Z[a] : f->Z_rotation;
  // omega rows, p columns: c z~ b~ G (a < 4) or c b~ G (a = 4); eta rows, p columns: c Z^T b~ G
  const Matrix3 M = a < 4 ? skew(z[a]) * b_skew : b_skew;
  for (unsigned int e = 0; e < 4; ++e)
    {
      Vector3 bG; // c b~ G e_e
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < 3; ++j) bG[i] += c * b_skew[i][j] * G[j][e];
      for (unsigned int i = 0; i < 3; ++i)
        D(row0 + 3 + i, col0 + 3 + e) += c * (M[i][0] * G[0][e] + M[i][1] * G[1][e] + M[i][2] * G[2][e]);
      for (unsigned int j = 0; j < n; ++j) D(row0 + 6 + j, col0 + 3 + e) += Z(0, j) * bG[0] + Z(1, j) * bG[1] + Z(2, j) * bG[2];
    }
  if (a == 4) return; // J_rotation does not depend on eta
  for (unsigned int i = 0; i < 3; ++i) // omega rows, eta columns: -b~ Z
    for (unsigned int j = 0; j < n; ++j) D(row0 + 3 + i, col0 + 7 + j) -= b_skew[i][0] * Z(0, j) + b_skew[i][1] * Z(1, j) + b_skew[i][2] * Z(2, j);
}

void Marker::axes(const double *q, const double *own, std::array<Vector3, 3> &e) const
{
  thread_local MarkerKinematics k;
  evaluate(q, own, k);
  e = k.axes;
}

void FixedMarker::axes(const double *q, const double *, std::array<Vector3, 3> &e) const
{
  // As evaluate(): e_c = A (a0_c + theta x a0_c), theta = Phi_th eta.
  if (body().n_v() == 0) // ground
    {
      for (unsigned int c = 0; c < 3; ++c)
        for (unsigned int b = 0; b < 3; ++b) e[c][b] = a0[b][c];
      return;
    }
  const Matrix3 A = geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}});
  Vector3 theta;
  for (unsigned int m = 0; m < body().n_modes(); ++m)
    for (unsigned int a = 0; a < 3; ++a) theta[a] += phi(3 + a, m) * q[7 + m];
  for (unsigned int c = 0; c < 3; ++c) e[c] = A * deformed_axis(c, theta);
}

Vector3 FixedMarker::deformed_axis(const unsigned int c, const Vector3 &theta) const
{
  Vector3 a_0;
  for (unsigned int b = 0; b < 3; ++b) a_0[b] = a0[b][c];
  return a_0 + cross_product_3d(theta, a_0);
}

void FixedMarker::evaluate(const double *q, const double *, MarkerKinematics &k) const
{
  const unsigned int nv = body().n_v();
  k.J_position.reinit(3, nv);
  k.J_rotation.reinit(3, nv);
  for (auto &J : k.J_axes) J.reinit(3, nv);
  if (nv == 0) // ground
    {
      k.position = Vector3(x0);
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int b = 0; b < 3; ++b) k.axes[a][b] = a0[b][a];
      return;
    }
  const unsigned int n = body().n_modes();
  const Vector3 R({q[0], q[1], q[2]});
  const Matrix3 A = geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}});
  Vector3 u(x0), theta;
  for (unsigned int m = 0; m < n; ++m)
    for (unsigned int a = 0; a < 3; ++a)
      {
        u[a] += phi(a, m) * q[7 + m];
        theta[a] += phi(3 + a, m) * q[7 + m];
      }
  k.position = R + A * u;

  // r' = R' - A u~ omega + A Phi_u eta'
  const Matrix3 Au = -A * skew(u);
  for (unsigned int a = 0; a < 3; ++a)
    {
      k.J_position(a, a) = 1;
      for (unsigned int b = 0; b < 3; ++b)
        {
          k.J_position(a, 3 + b) = Au[a][b];
          k.J_rotation(a, 3 + b) = A[a][b]; // omega_global = A (omega + Phi_th eta')
        }
      for (unsigned int m = 0; m < n; ++m)
        for (unsigned int b = 0; b < 3; ++b)
          {
            k.J_position(a, 6 + m) += A[a][b] * phi(b, m);
            k.J_rotation(a, 6 + m) += A[a][b] * phi(3 + b, m);
          }
    }

  // Axis e = A b, b = a0 + theta x a0:  e' = -A b~ omega - A a0~ Phi_th eta'
  for (unsigned int c = 0; c < 3; ++c)
    {
      Vector3 a_0;
      for (unsigned int b = 0; b < 3; ++b) a_0[b] = a0[b][c];
      const Vector3 b_c = deformed_axis(c, theta);
      k.axes[c] = A * b_c;
      const Matrix3 Ab = -A * skew(b_c), Aa = -A * skew(a_0);
      FullMatrix<double> &J = k.J_axes[c];
      for (unsigned int a = 0; a < 3; ++a)
        {
          for (unsigned int b = 0; b < 3; ++b) J(a, 3 + b) = Ab[a][b];
          for (unsigned int m = 0; m < n; ++m)
            for (unsigned int b = 0; b < 3; ++b) J(a, 6 + m) += Aa[a][b] * phi(3 + b, m);
        }
    }
}

std::unique_ptr<FixedMarker> FixedMarker::at_global_pose(const Body &body, std::string name, const Vector3 &position,
                                                         const Matrix3 &axes, const double *q,
                                                         const std::string &interface)
{
  if (body.is_ground()) return std::make_unique<FixedMarker>(body, std::move(name), Point<3>(position), axes);
  const Vector3 R({q[0], q[1], q[2]});
  const Matrix3 A = geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}});
  const Matrix3 frame = transpose(A) * axes;
  if (interface.empty())
    return std::make_unique<FixedMarker>(body, std::move(name), Point<3>(transpose(A) * (position - R)), frame);

  const auto *floating = dynamic_cast<const FloatingBody *>(&body);
  const reduction::ReducedBody *reduced = floating ? floating->source() : nullptr;
  if (!reduced) throw InputError("Interface", "body '" + body.name() + "' is not flexible; it has no interface '" + interface + "'");
  // Interfaces and output points alike carry 6 x n mode shapes (a probe reads a tip that is an
  // output point). A flexible body made rigid keeps their positions, without their modes.
  for (const auto *points : {&reduced->interfaces, &reduced->output_points})
    for (const auto &i : *points)
      if (i.name == interface)
        return body.n_modes() == 0 ? std::make_unique<FixedMarker>(body, std::move(name), i.position, frame)
                                   : std::make_unique<FixedMarker>(body, std::move(name), i.position, frame, i.modes);
  std::string allowed;
  for (const auto *points : {&reduced->interfaces, &reduced->output_points})
    for (const auto &i : *points) allowed += (allowed.empty() ? "" : ", ") + i.name;
  throw InputError("Interface", "body '" + body.name() + "' has no interface or output point '" + interface + "'; allowed: " + allowed);
}
} // namespace flextrack::multibody
