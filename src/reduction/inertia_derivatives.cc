// Analytic derivatives of the inertial residual r = M(A, eta) v_dot - Q_v of a floating-frame
// body (inertia_invariants.h), for the Jacobian of the equations of motion. Written out from the
// same invariant formulas as mass_matrix() and quadratic_velocity(), term by term:
//   r_R = m R'' + A h_R,  h_R = -S x omega' + I3 eta'' + omega x (omega x S) + 2 omega x I3 eta'
//   r_w = S x (A^T R'') + J omega' + M_wf eta'' + omega x J omega
//         + 2 sum_k eta'_k (tr(Ph_k) omega - Ph_k omega)
//   r_k = I3_k . (A^T R'') + Mwf_k . omega' + (M_ff eta'')_k + omega . Ph_k omega
//         - |omega|^2 tr(Ph_k) + 2 omega . sum_j eta'_j I5_jk
// with S = s + I3 eta, J(eta) = J_O + (2 tr Pe + tr Qee) 1 - Pe - Pe^T - Qee, Ph_k = P_k +
// sum_j eta_j Q_kj, Mwf_k = I4_k + sum_j eta_j I5_jk. Everything is polynomial in eta, omega and
// eta', so each derivative is one more contraction of the invariants: O(n^2) for the body,
// against O(n^3) for a difference quotient over its columns. The test oracle is that difference
// quotient (tests/unit/multibody_body_jacobian_test.cc).
#include <reduction/inertia_invariants.h>

namespace flextrack::reduction
{
using namespace dealii;

void FloatingFrameInertia::derivatives(const Tensor<2, 3> &A, const double *eta, const Tensor<1, 3> &w,
                                       const double *eta_dot, const double *v_dot, Derivatives &d) const
{
  const unsigned int size = 6 + n;
  d.d_eta.reinit(size, n);
  d.d_omega.reinit(size, 3);
  d.d_eta_dot.reinit(size, n);
  Tensor<1, 3> a, alpha; // R'' (global), omega' (body)
  if (v_dot)
    for (unsigned int i = 0; i < 3; ++i) a[i] = v_dot[i], alpha[i] = v_dot[3 + i];
  const Tensor<1, 3> a_body = transpose(A) * a;
  auto I3 = [&](const unsigned int k) { return Tensor<1, 3>({inv.I3(0, k), inv.I3(1, k), inv.I3(2, k)}); };

  // The state-dependent invariants, as in mass_matrix() and quadratic_velocity().
  const EtaTerms &t = eta_terms(eta);
  const std::vector<Tensor<2, 3>> &Ph = t.Ph;
  const Tensor<2, 3> &J = t.J;
  Tensor<1, 3> I3ed, I3edd;
  Tensor<2, 3> Ph_eta_dot; // sum_k eta'_k Ph_k
  thread_local std::vector<Tensor<1, 3>> coriolis; // sum_j eta'_j I5_jk (storage reused)
  coriolis.assign(n, Tensor<1, 3>());
  d.S = t.S;
  for (unsigned int k = 0; k < n; ++k)
    {
      const Tensor<1, 3> I3k = I3(k);
      I3ed += eta_dot[k] * I3k;
      if (v_dot) I3edd += v_dot[6 + k] * I3k;
      for (unsigned int j = 0; j < n; ++j) coriolis[k] += eta_dot[j] * i5[j * n + k];
      Ph_eta_dot += eta_dot[k] * Ph[k];
    }
  const Tensor<2, 3> one = unit_symmetric_tensor<3>();
  const Tensor<1, 3> Jw = J * w;
  const double w2 = w * w;
  d.h_R = -cross_product_3d(d.S, alpha) + I3edd + cross_product_3d(w, cross_product_3d(w, d.S)) + 2 * cross_product_3d(w, I3ed);

  auto set_column = [&](FullMatrix<double> &m, const unsigned int row0, const unsigned int c, const Tensor<1, 3> &x) {
    for (unsigned int i = 0; i < 3; ++i) m(row0 + i, c) = x[i];
  };

  // d/d eta_m
  for (unsigned int m = 0; m < n; ++m)
    {
      const Tensor<1, 3> I3m = I3(m);
      set_column(d.d_eta, 0, m, A * (-cross_product_3d(I3m, alpha) + cross_product_3d(w, cross_product_3d(w, I3m))));
      Tensor<2, 3> dQee; // d Qee / d eta_m = sum_j eta_j (Q_mj + Q_jm)
      for (unsigned int j = 0; j < n; ++j) dQee += eta[j] * (inv.Q[m * n + j] + inv.Q[j * n + m]);
      const Tensor<2, 3> dJ = (2 * trace(inv.P[m]) + trace(dQee)) * one - inv.P[m] - transpose(inv.P[m]) - dQee;
      Tensor<1, 3> rw = cross_product_3d(I3m, a_body) + dJ * alpha + cross_product_3d(w, dJ * w);
      for (unsigned int k = 0; k < n; ++k)
        {
          const Tensor<2, 3> &Qkm = inv.Q[k * n + m]; // d Ph_k / d eta_m
          if (v_dot) rw += v_dot[6 + k] * i5[m * n + k];
          rw += 2 * eta_dot[k] * (trace(Qkm) * w - Qkm * w);
          d.d_eta(6 + k, m) = i5[m * n + k] * alpha + w * (Qkm * w) - w2 * trace(Qkm);
        }
      set_column(d.d_eta, 3, m, rw);
    }

  // d/d omega_l
  for (unsigned int l = 0; l < 3; ++l)
    {
      Tensor<1, 3> e;
      e[l] = 1;
      set_column(d.d_omega, 0, l,
                 A * (cross_product_3d(e, cross_product_3d(w, d.S)) + cross_product_3d(w, cross_product_3d(e, d.S)) +
                      2 * cross_product_3d(e, I3ed)));
      set_column(d.d_omega, 3, l,
                 cross_product_3d(e, Jw) + cross_product_3d(w, J * e) + 2 * (trace(Ph_eta_dot) * e - Ph_eta_dot * e));
    }
  for (unsigned int k = 0; k < n; ++k)
    {
      const Tensor<1, 3> g = Ph[k] * w + transpose(Ph[k]) * w - 2 * trace(Ph[k]) * w + 2 * coriolis[k];
      for (unsigned int l = 0; l < 3; ++l) d.d_omega(6 + k, l) = g[l];
    }

  // d/d eta'_m
  for (unsigned int m = 0; m < n; ++m)
    {
      set_column(d.d_eta_dot, 0, m, A * (2 * cross_product_3d(w, I3(m))));
      set_column(d.d_eta_dot, 3, m, 2 * (trace(Ph[m]) * w - Ph[m] * w));
      for (unsigned int k = 0; k < n; ++k) d.d_eta_dot(6 + k, m) = 2 * (w * i5[m * n + k]);
    }
}
} // namespace flextrack::reduction
