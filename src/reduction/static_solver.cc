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

std::vector<StaticSolution> StaticSolver::solve(const std::vector<dealii::Vector<double>> &f) const
{
  const std::size_t n = K.m(), k = f.size();
  std::vector<double> B(n * k), X(n * k);
  for (std::size_t j = 0; j < k; ++j)
    for (std::size_t i = 0; i < n; ++i) B[j * n + i] = fixed.is_constrained(i) ? 0.0 : f[j][i];
  if (k > 0) factorization->solve_many(B.data(), X.data(), k);

  // One solve. The residual of a slender structure's solution is 1e-10..1e-9 of |f| and the
  // reactions inherit it; iterative refinement (residuals in double or in long double) and a
  // diagonal equilibration of K were tried: neither reduced it, and refinement moved the tip
  // deflection of the slender cantilever away from its closed form (2e-10 instead of 9e-11).
  std::vector<StaticSolution> solutions(k);
  for (std::size_t j = 0; j < k; ++j)
    {
      auto &s = solutions[j];
      s.u.reinit(n);
      for (std::size_t i = 0; i < n; ++i) s.u[i] = fixed.is_constrained(i) ? 0.0 : X[j * n + i];
      s.reaction.reinit(n);
      K.vmult(s.reaction, s.u);
      s.strain_energy = 0.5 * (s.u * s.reaction);
      s.reaction -= f[j];
      double worst = 0, scale = 0;
      for (std::size_t i = 0; i < n; ++i)
        {
          scale = std::max(scale, std::abs(f[j][i]));
          if (!fixed.is_constrained(i))
            {
              worst = std::max(worst, std::abs(s.reaction[i]));
              s.reaction[i] = 0; // round-off of the solve, not a reaction
            }
        }
      s.residual = scale > 0 ? worst / scale : worst;
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
