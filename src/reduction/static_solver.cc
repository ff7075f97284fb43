#include <base/solver_error.h>
#include <reduction/sparse_factorization.h>
#include <reduction/static_solver.h>

#include <Epetra_CrsMatrix.h>

#include <algorithm>
#include <cmath>
#include <sstream>

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
                           const dealii::AffineConstraints<double> &supports)
  : K(K_free), fixed(supports)
{
  const auto A = supported_copy(K_free, supports);
  factorization = std::make_unique<SparseFactorization>(A, A, 0.0, "cholmod");
}

StaticSolver::~StaticSolver() = default;

/// r = K u - f with every row's sum accumulated in long double (64-bit mantissa on x86): the
/// terms K_ij u_j of a bending solution are 1e4..1e6 times their sum, so a double sum loses the
/// digits that the reactions and the refinement need.
std::vector<long double> StaticSolver::accurate_residual(const dealii::Vector<double> &u, const dealii::Vector<double> &f) const
{
  const auto &a = K.trilinos_matrix();
  std::vector<long double> r(K.m());
  for (int row = 0; row < a.NumMyRows(); ++row)
    {
      int count = 0;
      double *values = nullptr;
      int *columns = nullptr;
      a.ExtractMyRowView(row, count, values, columns);
      long double sum = 0;
      for (int c = 0; c < count; ++c) sum += static_cast<long double>(values[c]) * u[a.ColMap().GID(columns[c])];
      const auto i = static_cast<std::size_t>(a.RowMap().GID(row));
      r[i] = sum - f[i];
    }
  return r;
}

std::vector<StaticSolution> StaticSolver::solve(const std::vector<dealii::Vector<double>> &f,
                                               const std::vector<dealii::Vector<double>> &prescribed) const
{
  const std::size_t n = K.m(), k = f.size();
  // u = g + x: g the prescribed support displacements (zero at free dofs), x zero at the
  // supports; K_ff x_f = f_f - (K g)_f. Scale of the residual test: the free rows' loads.
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
  if (k > 0) factorization->solve_many(B.data(), X.data(), k);

  std::vector<StaticSolution> solutions(k);
  for (std::size_t j = 0; j < k; ++j)
    {
      auto &s = solutions[j];
      s.u.reinit(n);
      for (std::size_t i = 0; i < n; ++i) s.u[i] = fixed.is_constrained(i) ? g[j][i] : X[j * n + i];
      // Iterative refinement with residuals summed in long double: the reactions are K u - f
      // at the supports, and their resultant balances the loads up to R^T K u (the assembled K's
      // round-off on the rigid motions R, times u) plus the free rows of K u - f, the solve's
      // residual. One solve leaves the latter at 1e-9..1e-8 of |f| on slender solids
      // (cond(K) about 1e9); refined, it falls below 1e-10 and R^T K u is what remains.
      std::vector<long double> r = accurate_residual(s.u, f[j]);
      const auto free_size = [&](const std::vector<long double> &e) {
        long double worst = 0;
        for (std::size_t i = 0; i < n; ++i)
          if (!fixed.is_constrained(i)) worst = std::max(worst, std::abs(e[i]));
        return static_cast<double>(worst);
      };
      double worst = free_size(r);
      for (unsigned int step = 0; step < max_refinements && worst > 0; ++step)
        {
          std::vector<double> b(n), du(n);
          for (std::size_t i = 0; i < n; ++i) b[i] = fixed.is_constrained(i) ? 0.0 : -static_cast<double>(r[i]);
          factorization->solve(b.data(), du.data());
          dealii::Vector<double> u = s.u;
          for (std::size_t i = 0; i < n; ++i)
            if (!fixed.is_constrained(i)) u[i] += du[i];
          auto r_next = accurate_residual(u, f[j]);
          const double next = free_size(r_next);
          if (!(next < worst)) break;
          s.u = u;
          r = std::move(r_next);
          worst = next;
        }
      s.reaction.reinit(n);
      for (std::size_t i = 0; i < n; ++i) s.reaction[i] = fixed.is_constrained(i) ? static_cast<double>(r[i]) : 0.0;
      // U = u^T K u / 2 = (u . f + u . r) / 2, r = K u - f; u = 0 where r is a reaction.
      long double energy = 0;
      for (std::size_t i = 0; i < n; ++i) energy += static_cast<long double>(s.u[i]) * (f[j][i] + r[i]);
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
