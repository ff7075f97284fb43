#include <fem/curved_beam_model.h>
#include <reduction/craig_bampton.h>
#include <reduction/linear_solver.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>

namespace flextrack::reduction
{
using namespace dealii;

namespace
{
/// Phi^T K Phi and Phi^T M Phi of a model's matrices.
void project(ReducedModel &r, const TrilinosWrappers::SparseMatrix &K, const TrilinosWrappers::SparseMatrix &M)
{
  const unsigned int n = r.basis.size();
  r.stiffness.reinit(n, n);
  r.mass.reinit(n, n);
  Vector<double> Kphi(K.m()), Mphi(M.m());
  for (unsigned int b = 0; b < n; ++b)
    {
      K.vmult(Kphi, r.basis[b]);
      M.vmult(Mphi, r.basis[b]);
      for (unsigned int a = 0; a < n; ++a)
        {
          r.stiffness(a, b) = r.basis[a] * Kphi;
          r.mass(a, b) = r.basis[a] * Mphi;
        }
    }
}
} // namespace

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
  project(r, full.stiffness_matrix(), full.mass_matrix());
  return r;
}


ReducedModel track_load_basis(const fem::Arm &arm, const unsigned int n_normal_modes, const unsigned int n_stations,
                              const ModalSettings &settings)
{
  const fem::CurvedBeamModel model(arm);
  ModalSettings modal = settings;
  modal.n_modes = n_normal_modes;
  ReducedModel r;
  r.n_normal_modes = n_normal_modes;
  r.basis = lowest_modes(model, modal).shapes; // mass-orthonormal already
  const double L = arm.curve->length();
  Vector<double> Mv(model.n_dofs());
  for (unsigned int k = 1; k <= n_stations; ++k)
    for (unsigned int d = 0; d < 3; ++d)
      {
        Vector<double> v = solve_direct(model.stiffness_matrix(), model.point_load(k * L / n_stations,
                                                                                     Tensor<1, 3>(Point<3>::unit_vector(d))));
        model.mass_matrix().vmult(Mv, v);
        const double original = std::sqrt(v * Mv);
        for (int pass = 0; pass < 2; ++pass) // twice is enough (Kahan: "twice is enough")
          for (const auto &phi : r.basis)
            {
              model.mass_matrix().vmult(Mv, phi);
              v.add(-(v * Mv), phi);
            }
        model.mass_matrix().vmult(Mv, v);
        const double norm = std::sqrt(v * Mv);
        if (norm > 1e-8 * original)
          {
            v /= norm;
            r.basis.push_back(std::move(v));
          }
      }
  project(r, model.stiffness_matrix(), model.mass_matrix());
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
    f.push_back(frequency_hz(K.eigenvalue(i).real()));
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
