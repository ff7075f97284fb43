// Exact derivatives of a floating-frame body's equations of motion F = M(q) v' - Q(q, v, v'),
// for the DAE Jacobian (system_jacobian.cc). The inertial terms come from
// FloatingFrameInertia::derivatives; this file adds the Euler-parameter columns (through
// dA/dp), gravity, the elastic and damping forces and the geometric stiffness of the inertial
// loads, K_eff = K + sum_c c_c(omega, b, omega') G_c with b = A^T (R'' - g) (body.cc, forces()).
//
// Why the Euler-parameter columns take this form: A enters F only as A h_R in the R rows and
// through b in the omega and modal rows (M_wR R'' and the gravity torque combine to S x b, M_fR
// R'' and gravity to I3_k . b), so dF/dp_i = (dA/dp_i h_R, S x db_i, I3_k . db_i + stiffening)
// with db_i = (dA/dp_i)^T (R'' - g).
#include <multibody/body.h>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
/// dA/dp_i of the rotation matrix A(p / |p|) of geometry::rotation_matrix (p not normalised):
/// A = 1 + s W(p), s = 2 / |p|^2, W quadratic in p.
std::array<Matrix3, 4> rotation_matrix_derivatives(const geometry::EulerParameters &p)
{
  const double n2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3], s = 2.0 / n2;
  const double e0 = p[0], e1 = p[1], e2 = p[2], e3 = p[3];
  Matrix3 W;
  W[0][0] = -(e2 * e2 + e3 * e3), W[0][1] = e1 * e2 - e0 * e3, W[0][2] = e1 * e3 + e0 * e2;
  W[1][0] = e1 * e2 + e0 * e3, W[1][1] = -(e1 * e1 + e3 * e3), W[1][2] = e2 * e3 - e0 * e1;
  W[2][0] = e1 * e3 - e0 * e2, W[2][1] = e2 * e3 + e0 * e1, W[2][2] = -(e1 * e1 + e2 * e2);
  // dW / dp_i, entry by entry (each entry's gradient (d/de0, d/de1, d/de2, d/de3)).
  const double dW[3][3][4] = {{{0, 0, -2 * e2, -2 * e3}, {-e3, e2, e1, -e0}, {e2, e3, e0, e1}},
                              {{e3, e2, e1, e0}, {0, -2 * e1, 0, -2 * e3}, {-e1, -e0, e3, e2}},
                              {{-e2, e3, -e0, e1}, {e1, e0, e3, e2}, {0, -2 * e1, -2 * e2, 0}}};
  std::array<Matrix3, 4> dA;
  for (unsigned int i = 0; i < 4; ++i)
    {
      const double ds = -4 * p[i] / (n2 * n2);
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int b = 0; b < 3; ++b) dA[i][a][b] = ds * W[a][b] + s * dW[a][b][i];
    }
  return dA;
}
} // namespace

void FloatingBody::equation_jacobians(const double *q, const double *v, const double *v_dot, const Vector3 &gravity,
                                      FullMatrix<double> &dF_dq, FullMatrix<double> &dF_dv,
                                      FullMatrix<double> &dF_dv_dot) const
{
  const FrameState f = frame(q, v);
  reduction::FloatingFrameInertia::Derivatives d;
  inertia->derivatives(f.A, f.eta.begin(), f.omega, f.eta_dot.begin(), v_dot, d);
  inertia->mass_matrix(f.A, f.eta.begin(), dF_dv_dot);
  dF_dq.reinit(6 + n, 7 + n);
  dF_dv.reinit(6 + n, 6 + n);

  Vector3 a_minus_g = -gravity, angular_acceleration;
  if (v_dot)
    for (unsigned int i = 0; i < 3; ++i) a_minus_g[i] += v_dot[i], angular_acceleration[i] = v_dot[3 + i];
  const Vector3 b = transpose(f.A) * a_minus_g; // the frame's acceleration less gravity, body axes
  const Vector3 g_body = transpose(f.A) * gravity;
  // G_c eta, c = 0..11 (reduced_body.h: omega products, then b, then omega').
  std::vector<Vector<double>> G_eta(stiffening ? 12 : 0, Vector<double>(n));
  for (unsigned int c = 0; c < G_eta.size(); ++c) reduced->geometric_stiffness[c].vmult(G_eta[c], f.eta);
  auto I3 = [&](const unsigned int k) { return Vector3({inv.I3(0, k), inv.I3(1, k), inv.I3(2, k)}); };

  // Euler-parameter columns 3..6 (R's columns are zero: nothing depends on the position).
  const auto dA = rotation_matrix_derivatives(f.p);
  for (unsigned int i = 0; i < 4; ++i)
    {
      const Vector3 dAh = dA[i] * d.h_R, db = transpose(dA[i]) * a_minus_g, Sxdb = cross_product_3d(d.S, db);
      for (unsigned int r = 0; r < 3; ++r)
        {
          dF_dq(r, 3 + i) = dAh[r];
          dF_dq(3 + r, 3 + i) = Sxdb[r];
        }
      for (unsigned int k = 0; k < n; ++k)
        {
          double x = I3(k) * db;
          if (stiffening)
            for (unsigned int l = 0; l < 3; ++l) x += db[l] * G_eta[6 + l][k];
          dF_dq(6 + k, 3 + i) = x;
        }
    }
  // Modal columns: inertia, the gravity torque -S x g_body, K_eff.
  const FullMatrix<double> K_eff =
    stiffening ? reduction::stiffness_with_inertial_loads(*reduced, f.omega, b, angular_acceleration) : K;
  for (unsigned int m = 0; m < n; ++m)
    {
      const Vector3 torque = cross_product_3d(I3(m), g_body);
      for (unsigned int r = 0; r < 6 + n; ++r) dF_dq(r, 7 + m) = d.d_eta(r, m);
      for (unsigned int r = 0; r < 3; ++r) dF_dq(3 + r, 7 + m) -= torque[r];
      for (unsigned int k = 0; k < n; ++k) dF_dq(6 + k, 7 + m) += K_eff(k, m);
    }
  // Velocity columns: R' none; omega (inertia, and K_eff through c_0..5 = omega products);
  // eta' (inertia, damping).
  for (unsigned int r = 0; r < 6 + n; ++r)
    {
      for (unsigned int l = 0; l < 3; ++l) dF_dv(r, 3 + l) = d.d_omega(r, l);
      for (unsigned int m = 0; m < n; ++m) dF_dv(r, 6 + m) = d.d_eta_dot(r, m) + (r >= 6 ? D(r - 6, m) : 0.0);
    }
  if (!stiffening) return;
  const Vector3 &w = f.omega;
  for (unsigned int k = 0; k < n; ++k)
    {
      // d(c_c)/d omega_l for c_c = w0^2, w1^2, w2^2, w0 w1, w0 w2, w1 w2.
      dF_dv(6 + k, 3) += 2 * w[0] * G_eta[0][k] + w[1] * G_eta[3][k] + w[2] * G_eta[4][k];
      dF_dv(6 + k, 4) += 2 * w[1] * G_eta[1][k] + w[0] * G_eta[3][k] + w[2] * G_eta[5][k];
      dF_dv(6 + k, 5) += 2 * w[2] * G_eta[2][k] + w[0] * G_eta[4][k] + w[1] * G_eta[5][k];
      // b = A^T (R'' - g): db / dR''_l = row l of A; c_9..11 = omega'.
      for (unsigned int l = 0; l < 3; ++l)
        {
          for (unsigned int c = 0; c < 3; ++c) dF_dv_dot(6 + k, l) += f.A[l][c] * G_eta[6 + c][k];
          dF_dv_dot(6 + k, 3 + l) += G_eta[9 + l][k];
        }
    }
}
} // namespace flextrack::multibody
