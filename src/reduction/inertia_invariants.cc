#include <geometry/rotation.h>
#include <reduction/inertia_invariants.h>

#include <deal.II/lac/lapack_full_matrix.h>

namespace flextrack::reduction
{
using namespace dealii;

using geometry::skew;

Point<3> InertiaInvariants::centre_of_mass() const { return Point<3>(first_moment / mass); }

Tensor<2, 3> InertiaInvariants::inertia_about_centre_of_mass() const
{
  const Tensor<1, 3> c = first_moment / mass;
  return inertia_origin - mass * ((c * c) * unit_symmetric_tensor<3>() - outer_product(c, c));
}

Tensor<1, 3> InertiaInvariants::I5(const unsigned int j, const unsigned int k) const
{
  const Tensor<2, 3> &q = Q[j * n_modes() + k];
  return Tensor<1, 3>({q[1][2] - q[2][1], q[2][0] - q[0][2], q[0][1] - q[1][0]});
}

FloatingFrameInertia::FloatingFrameInertia(const InertiaInvariants &invariants, const FullMatrix<double> &modal_mass)
  : n(invariants.n_modes()), inv(invariants), modal_mass(modal_mass), i5(n * n)
{
  for (unsigned int j = 0; j < n; ++j)
    for (unsigned int k = 0; k < n; ++k) i5[j * n + k] = inv.I5(j, k);
}

void FloatingFrameInertia::mass_matrix(const Tensor<2, 3> &A, const Vector<double> &eta, FullMatrix<double> &M) const
{
  M.reinit(6 + n, 6 + n);
  // S = s + I3 eta; J = J_O + 2 tr(Pe) 1 - Pe - Pe^T + tr(Qee) 1 - Qee.
  Tensor<1, 3> S = inv.first_moment;
  Tensor<2, 3> Pe, Qee;
  for (unsigned int k = 0; k < n; ++k)
    {
      for (unsigned int a = 0; a < 3; ++a) S[a] += inv.I3(a, k) * eta[k];
      Pe += eta[k] * inv.P[k];
      Tensor<2, 3> row; // sum_j eta_j Q_jk
      for (unsigned int j = 0; j < n; ++j) row += eta[j] * inv.Q[j * n + k];
      Qee += eta[k] * row;
    }
  const Tensor<2, 3> J = inv.inertia_origin + (2 * trace(Pe) + trace(Qee)) * unit_symmetric_tensor<3>() - Pe -
                         transpose(Pe) - Qee;
  const Tensor<2, 3> MRw = -A * skew(S);
  for (unsigned int a = 0; a < 3; ++a)
    {
      M(a, a) = inv.mass;
      for (unsigned int b = 0; b < 3; ++b)
        {
          M(a, 3 + b) = M(3 + b, a) = MRw[a][b];
          M(3 + a, 3 + b) = J[a][b];
        }
    }
  for (unsigned int k = 0; k < n; ++k)
    {
      Tensor<1, 3> AI3, Mwf; // A I3_k; I4_k + sum_j eta_j I5_jk
      for (unsigned int a = 0; a < 3; ++a)
        {
          Mwf[a] = inv.I4(a, k);
          for (unsigned int b = 0; b < 3; ++b) AI3[a] += A[a][b] * inv.I3(b, k);
        }
      for (unsigned int j = 0; j < n; ++j) Mwf += eta[j] * i5[j * n + k];
      for (unsigned int a = 0; a < 3; ++a)
        {
          M(a, 6 + k) = M(6 + k, a) = AI3[a];
          M(3 + a, 6 + k) = M(6 + k, 3 + a) = Mwf[a];
        }
      for (unsigned int j = 0; j < n; ++j) M(6 + j, 6 + k) = modal_mass(j, k);
    }
}

void FloatingFrameInertia::quadratic_velocity(const Tensor<2, 3> &A, const Vector<double> &eta,
                                              const Tensor<1, 3> &w, const Vector<double> &eta_dot,
                                              Vector<double> &Qv) const
{
  Qv.reinit(6 + n);
  Tensor<1, 3> S = inv.first_moment, I3ed; // I3 etad
  Tensor<2, 3> Pe, Qee;
  thread_local std::vector<Tensor<2, 3>> Ph; // Ph_k = P_k + sum_j eta_j Q_kj (storage reused)
  Ph.resize(n);
  for (unsigned int k = 0; k < n; ++k)
    {
      for (unsigned int a = 0; a < 3; ++a)
        {
          S[a] += inv.I3(a, k) * eta[k];
          I3ed[a] += inv.I3(a, k) * eta_dot[k];
        }
      Ph[k] = inv.P[k];
      for (unsigned int j = 0; j < n; ++j) Ph[k] += eta[j] * inv.Q[k * n + j];
      Pe += eta[k] * inv.P[k];
    }
  for (unsigned int k = 0; k < n; ++k) Qee += eta[k] * (Ph[k] - inv.P[k]);
  const Tensor<2, 3> J = inv.inertia_origin + (2 * trace(Pe) + trace(Qee)) * unit_symmetric_tensor<3>() - Pe -
                         transpose(Pe) - Qee;
  const Tensor<1, 3> QR = -(A * (cross_product_3d(w, cross_product_3d(w, S)) + 2 * cross_product_3d(w, I3ed)));
  Tensor<1, 3> Qw = -cross_product_3d(w, J * w);
  for (unsigned int k = 0; k < n; ++k) Qw -= 2 * eta_dot[k] * (trace(Ph[k]) * w - Ph[k] * w);
  for (unsigned int a = 0; a < 3; ++a)
    {
      Qv[a] = QR[a];
      Qv[3 + a] = Qw[a];
    }
  const double w2 = w * w;
  for (unsigned int k = 0; k < n; ++k)
    {
      Tensor<1, 3> coriolis; // sum_j etad_j I5_jk
      for (unsigned int j = 0; j < n; ++j) coriolis += eta_dot[j] * i5[j * n + k];
      Qv[6 + k] = -(w * (Ph[k] * w) - w2 * trace(Ph[k]) + 2 * (w * coriolis));
    }
}
} // namespace flextrack::reduction
