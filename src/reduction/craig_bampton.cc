#include <fem/curved_beam_model.h>
#include <reduction/craig_bampton.h>
#include <reduction/linear_solver.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>

namespace flextrack::reduction
{
using namespace dealii;

ReducedModel craig_bampton(const fem::Arm &arm, const double interface_s, const unsigned int n_normal_modes,
                           const ModalSettings &settings)
{
  // Both models get a node at the interface (a free "support" places one), so their meshes and
  // dof numbers are the same; the fixed-interface model clamps it.
  fem::Arm full_arm = arm, fixed_arm = arm;
  full_arm.supports.push_back({interface_s, fem::SupportKind::free});
  fixed_arm.supports.push_back({interface_s, fem::SupportKind::clamped});
  const fem::CurvedBeamModel full(full_arm), fixed(fixed_arm);

  ReducedModel r;
  r.n_normal_modes = n_normal_modes;
  for (unsigned int i = 0; i < full.n_dofs(); ++i)
    if (fixed.constraints().is_constrained(i) && !full.constraints().is_constrained(i)) r.interface_dofs.push_back(i);

  ModalSettings fixed_settings = settings;
  fixed_settings.n_modes = n_normal_modes;
  r.basis = lowest_modes(fixed, fixed_settings).shapes;

  // Constraint modes: K u = 0 away from the interface, u = e_j on it (supports stay fixed).
  IndexSet prescribed(full.n_dofs());
  for (const auto i : r.interface_dofs) prescribed.add_index(i);
  for (const auto j : r.interface_dofs)
    {
      Vector<double> values(full.n_dofs());
      values[j] = 1.0;
      r.basis.push_back(solve_with_prescribed_values(full.stiffness_matrix(), prescribed, values));
    }

  // Reduced matrices Phi^T K Phi and Phi^T M Phi (supported dofs vanish in every column).
  const unsigned int n = r.basis.size();
  r.stiffness.reinit(n, n);
  r.mass.reinit(n, n);
  Vector<double> Kphi(full.n_dofs()), Mphi(full.n_dofs());
  for (unsigned int b = 0; b < n; ++b)
    {
      full.stiffness_matrix().vmult(Kphi, r.basis[b]);
      full.mass_matrix().vmult(Mphi, r.basis[b]);
      for (unsigned int a = 0; a < n; ++a)
        {
          r.stiffness(a, b) = r.basis[a] * Kphi;
          r.mass(a, b) = r.basis[a] * Mphi;
        }
    }
  return r;
}

std::vector<double> ReducedModel::frequencies_hz() const
{
  LAPACKFullMatrix<double> K(stiffness.m()), M(mass.m());
  K = stiffness;
  M = mass;
  std::vector<Vector<double>> vectors(stiffness.m(), Vector<double>(stiffness.m()));
  K.compute_generalized_eigenvalues_symmetric(M, vectors);
  std::vector<double> f;
  for (unsigned int i = 0; i < stiffness.m(); ++i)
    {
      const double l = K.eigenvalue(i).real();
      f.push_back(std::copysign(std::sqrt(std::abs(l)), l) / (2 * M_PI));
    }
  std::sort(f.begin(), f.end());
  return f;
}

Vector<double> ReducedModel::static_response(const Vector<double> &f) const
{
  const unsigned int n = basis.size();
  Vector<double> g(n), q(n), u(basis[0].size());
  for (unsigned int a = 0; a < n; ++a) g[a] = basis[a] * f;
  LAPACKFullMatrix<double> K(n);
  K = stiffness;
  K.compute_lu_factorization();
  q = g;
  K.solve(q);
  for (unsigned int a = 0; a < n; ++a) u.add(q[a], basis[a]);
  return u;
}
} // namespace flextrack::reduction
