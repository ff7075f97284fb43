#include <base/solver_error.h>
#include <reduction/sparse_factorization.h>
#include <reduction/static_solver.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace flextrack::reduction
{
namespace
{
/// K_free with the rows and columns of the supported dofs zeroed and their diagonal kept (1 where
/// it is not positive), so that u = 0 there and the rest of the system is untouched.
dealii::TrilinosWrappers::SparseMatrix supported_copy(const dealii::TrilinosWrappers::SparseMatrix &K_free,
                                                      const dealii::AffineConstraints<double> &supports)
{
  dealii::TrilinosWrappers::SparseMatrix A;
  A.copy_from(K_free);
  auto &a = const_cast<Epetra_CrsMatrix &>(A.trilinos_matrix());
  for (int r = 0; r < a.NumMyRows(); ++r)
    {
      int count = 0;
      double *values = nullptr;
      int *columns = nullptr;
      a.ExtractMyRowView(r, count, values, columns);
      const auto i = static_cast<dealii::types::global_dof_index>(a.RowMap().GID(r));
      const bool fixed_row = supports.is_constrained(i);
      for (int c = 0; c < count; ++c)
        {
          const auto j = static_cast<dealii::types::global_dof_index>(a.ColMap().GID(columns[c]));
          if (i == j)
            {
              if (fixed_row && !(values[c] > 0)) values[c] = 1;
            }
          else if (fixed_row || supports.is_constrained(j))
            values[c] = 0;
        }
    }
  return A;
}
} // namespace

StaticSolver::StaticSolver(const dealii::TrilinosWrappers::SparseMatrix &K_free,
                           const dealii::AffineConstraints<double> &supports, StaticSolverSettings solver_settings)
  : K(K_free), fixed(supports), settings(std::move(solver_settings))
{
  if (!settings.iterative)
    {
      // CHOLMOD's input is built from K_free's rows directly, the supported rows and columns
      // left out: no copy of K (a third of the memory before the factor).
      std::vector<bool> held(K_free.m());
      for (std::size_t i = 0; i < held.size(); ++i) held[i] = supports.is_constrained(i);
      factorization = std::make_unique<SparseFactorization>(K_free, held);
      return;
    }
  refuse_mechanism();
  supported = std::make_unique<dealii::TrilinosWrappers::SparseMatrix>(supported_copy(K_free, supports));
  // Smoothed aggregation for an elliptic problem of higher-order elements (ML's defaults as
  // deal.II sets them: Chebyshev smoother, KLU on the coarsest level), with the rigid motions as
  // the near-null space: ML builds its coarse spaces from them.
  dealii::TrilinosWrappers::PreconditionAMG::AdditionalData data(true, true);
  Teuchos::ParameterList parameters;
  std::unique_ptr<Epetra_MultiVector> unused;
  data.set_parameters(parameters, unused, *supported);
  const std::size_t n = K.m();
  null_space.assign(n * settings.rigid_modes.size(), 0.0);
  for (std::size_t k = 0; k < settings.rigid_modes.size(); ++k)
    std::copy(settings.rigid_modes[k].begin(), settings.rigid_modes[k].end(), null_space.begin() + k * n);
  if (!settings.rigid_modes.empty())
    {
      parameters.set("null space: type", "pre-computed");
      parameters.set("null space: dimension", static_cast<int>(settings.rigid_modes.size()));
      parameters.set("null space: vectors", null_space.data());
    }
  multigrid = std::make_unique<dealii::TrilinosWrappers::PreconditionAMG>();
  multigrid->initialize(*supported, parameters);
  settings.rigid_modes.clear(); // copied into null_space
}

void StaticSolver::refuse_mechanism() const
{
  // The factor finds a mechanism as a zero pivot; CG would instead converge to one of many
  // solutions (a load orthogonal to the free motion) or not at all. The supports hold every
  // rigid motion iff the rigid modes restricted to the supported dofs are independent: the
  // Gram matrix of the normalised modes there has no (near-)zero eigenvalue.
  const auto &R = settings.rigid_modes;
  const unsigned int m = R.size();
  if (m == 0) return;
  dealii::LAPACKFullMatrix<double> gram(m, m);
  for (unsigned int a = 0; a < m; ++a)
    for (unsigned int b = 0; b <= a; ++b)
      {
        double sum = 0;
        for (std::size_t i = 0; i < R[a].size(); ++i)
          if (fixed.is_constrained(i)) sum += R[a][i] * R[b][i];
        gram(a, b) = gram(b, a) = sum / (R[a].l2_norm() * R[b].l2_norm());
      }
  gram.compute_eigenvalues();
  double smallest = std::numeric_limits<double>::max(), largest = 0;
  for (unsigned int a = 0; a < m; ++a)
    {
      smallest = std::min(smallest, gram.eigenvalue(a).real());
      largest = std::max(largest, gram.eigenvalue(a).real());
    }
  if (!(smallest > 1e-12 * largest))
    throw SolverError("the supports do not hold the structure against every rigid motion (a mechanism); add supports");
}

void StaticSolver::solve_supported(const double *b, double *x, const std::size_t k) const
{
  if (factorization)
    {
      factorization->solve_many(b, x, k);
      return;
    }
  const std::size_t n = K.m();
  for (std::size_t j = 0; j < k; ++j)
    {
      dealii::Vector<double> rhs(b + j * n, b + (j + 1) * n), u(n);
      dealii::SolverControl control(settings.max_iterations, settings.tolerance * rhs.l2_norm());
      dealii::SolverCG<dealii::Vector<double>> cg(control);
      try
        {
          cg.solve(*supported, u, rhs, *multigrid);
        }
      catch (const dealii::SolverControl::NoConvergence &e)
        {
          std::ostringstream m;
          m << "conjugate gradients did not reach the relative residual " << settings.tolerance << " in "
            << e.last_step << " iterations (reached " << e.last_residual / std::max(rhs.l2_norm(), 1e-300)
            << "); use 'Static/Linear solver = direct' or a larger 'Static/Solver tolerance'";
          throw SolverError(m.str());
        }
      cg_iterations += control.last_step();
      std::copy(u.begin(), u.end(), x + j * n);
    }
}

StaticSolver::~StaticSolver() = default;

std::vector<long double> long_double_product(const dealii::TrilinosWrappers::SparseMatrix &A,
                                             const std::vector<long double> &u)
{
  const auto &a = A.trilinos_matrix();
  std::vector<long double> Au(A.m(), 0.0L);
  for (int row = 0; row < a.NumMyRows(); ++row)
    {
      int count = 0;
      double *values = nullptr;
      int *columns = nullptr;
      a.ExtractMyRowView(row, count, values, columns);
      long double sum = 0;
      for (int c = 0; c < count; ++c) sum += static_cast<long double>(values[c]) * u[a.ColMap().GID(columns[c])];
      Au[static_cast<std::size_t>(a.RowMap().GID(row))] = sum;
    }
  return Au;
}

/// r = K u - f with K u summed in long double (long_double_product), or from the model's own
/// cell-by-cell internal forces (StaticSolverSettings::internal_forces).
std::vector<long double> StaticSolver::accurate_residual(const std::vector<long double> &u,
                                                         const dealii::Vector<double> &f) const
{
  std::vector<long double> r = settings.internal_forces ? settings.internal_forces(u) : long_double_product(K, u);
  for (std::size_t i = 0; i < r.size(); ++i) r[i] -= f[i];
  return r;
}

std::vector<StaticSolution> StaticSolver::solve(const std::vector<dealii::Vector<double>> &f,
                                               const std::vector<dealii::Vector<double>> &prescribed) const
{
  const std::size_t n = K.m(), k = f.size();
  // u = g + x: g the prescribed support displacements (zero at free dofs), x zero at the
  // supports; K_ff x_f = f_f - (K g)_f. Scale of the residual test: the free rows' loads.
  if (!prescribed.empty() && prescribed.size() != k)
    throw std::invalid_argument("StaticSolver::solve: one prescribed vector per load vector");
  for (const auto &p : prescribed)
    if (p.size() != n) throw std::invalid_argument("StaticSolver::solve: prescribed vector of the wrong length");
  std::vector<dealii::Vector<double>> g(k, dealii::Vector<double>(n));
  std::vector<double> B(n * k), X(n * k), scale(k, 0.0);
  for (std::size_t j = 0; j < k; ++j)
    {
      if (j < prescribed.size())
        for (std::size_t i = 0; i < n; ++i)
          if (fixed.is_constrained(i)) g[j][i] = prescribed[j][i];
      dealii::Vector<double> Kg(n);
      if (g[j].linfty_norm() > 0) K.vmult(Kg, g[j]);
      for (std::size_t i = 0; i < n; ++i)
        if (!fixed.is_constrained(i))
          {
            B[j * n + i] = f[j][i] - Kg[i];
            scale[j] = std::max({scale[j], std::abs(f[j][i]), std::abs(Kg[i])});
          }
    }
  if (k > 0) solve_supported(B.data(), X.data(), k);

  std::vector<StaticSolution> solutions(k);
  for (std::size_t j = 0; j < k; ++j)
    {
      auto &s = solutions[j];
      s.u.reinit(n);
      for (std::size_t i = 0; i < n; ++i) s.u[i] = fixed.is_constrained(i) ? g[j][i] : X[j * n + i];
      // Iterative refinement with residuals summed in long double, the solution itself kept in
      // long double (u_ld): the reactions are K u - f at the supports, and their resultant
      // balances the loads up to R^T K u (the assembled K's round-off on the rigid motions R,
      // times u) plus the free rows of K u - f, the solve's residual. One solve leaves the latter
      // at 1e-9..1e-8 of |f| on slender solids (cond(K) about 1e9); a double u cannot take it
      // below eps |K| |u| per row, a long-double one can. With the model's internal forces
      // (rigid motions taken out cell by cell) R^T K u goes too.
      std::vector<long double> u_ld(s.u.begin(), s.u.end());
      std::vector<long double> r = accurate_residual(u_ld, f[j]);
      const auto free_size = [&](const std::vector<long double> &e) {
        long double worst = 0;
        for (std::size_t i = 0; i < n; ++i)
          if (!fixed.is_constrained(i)) worst = std::max(worst, std::abs(e[i]));
        return static_cast<double>(worst);
      };
      double worst = free_size(r);
      // Refined only with the factor, where a step costs one solve: a step of the iterative
      // solver is a whole new CG solve, and CG's own residual reaches that of a refined factor
      // solution (2.9e-10 against 3.1e-11 of max |f| on the 74k-dof block, tolerance 1e-10).
      const unsigned int refinements = factorization ? max_refinements : 0;
      for (unsigned int step = 0; step < refinements && worst > 0; ++step)
        {
          std::vector<double> b(n), du(n);
          for (std::size_t i = 0; i < n; ++i) b[i] = fixed.is_constrained(i) ? 0.0 : -static_cast<double>(r[i]);
          solve_supported(b.data(), du.data(), 1);
          std::vector<long double> u_next = u_ld;
          for (std::size_t i = 0; i < n; ++i)
            if (!fixed.is_constrained(i)) u_next[i] += du[i];
          auto r_next = accurate_residual(u_next, f[j]);
          const double next = free_size(r_next);
          if (!(next < worst)) break;
          u_ld = std::move(u_next);
          r = std::move(r_next);
          worst = next;
        }
      for (std::size_t i = 0; i < n; ++i) s.u[i] = static_cast<double>(u_ld[i]);
      s.reaction.reinit(n);
      for (std::size_t i = 0; i < n; ++i) s.reaction[i] = fixed.is_constrained(i) ? static_cast<double>(r[i]) : 0.0;
      // U = u^T K u / 2 = (u . f + u . r) / 2, r = K u - f; u = 0 where r is a reaction.
      long double energy = 0;
      for (std::size_t i = 0; i < n; ++i) energy += u_ld[i] * (f[j][i] + r[i]);
      s.strain_energy = static_cast<double>(energy / 2);
      s.residual = scale[j] > 0 ? worst / scale[j] : worst;
      if (!(s.residual < 1e-4))
        {
          std::ostringstream m;
          m << "the static solution does not satisfy K u = f (relative residual " << s.residual
            << "): the supports do not hold the structure against every rigid motion (a mechanism); add supports";
          throw SolverError(m.str());
        }
    }
  return solutions;
}
} // namespace flextrack::reduction
