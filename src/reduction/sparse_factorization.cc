#include <reduction/modal_solver.h>
#include <reduction/sparse_factorization.h>

#include <Amesos.h>
#include <Amesos_BaseSolver.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_Vector.h>
#include <Teuchos_ParameterList.hpp>
#include <cholmod.h>

namespace flextrack::reduction
{
struct SparseFactorization::Cholmod
{
  cholmod_common common;
  cholmod_factor *factor = nullptr;
  cholmod_dense *rhs = nullptr;
  Cholmod() { cholmod_start(&common); }
  ~Cholmod()
  {
    if (factor) cholmod_free_factor(&factor, &common);
    if (rhs) cholmod_free_dense(&rhs, &common);
    cholmod_finish(&common);
  }
};

SparseFactorization::SparseFactorization(const dealii::TrilinosWrappers::SparseMatrix &K,
                                         const dealii::TrilinosWrappers::SparseMatrix &M, const double sigma,
                                         const std::string &method)
{
  if (method == "cholmod" && factorize_with_cholmod(K, M, sigma))
    return;
  // Not positive definite (a positive shift), or another method asked for: LDL^T or LU.
  matrix.copy_from(K);
  matrix.add(-sigma, M);
  factorize_with_amesos(method == "klu" ? "klu" : "mumps");
}

bool SparseFactorization::factorize_with_cholmod(const dealii::TrilinosWrappers::SparseMatrix &K,
                                                 const dealii::TrilinosWrappers::SparseMatrix &M, const double sigma)
{
  // The lower triangle of A in compressed columns = the upper triangle of its rows, read
  // straight from Epetra (deal.II's row iterators copy a row per step), two passes: count, fill.
  cholmod = std::make_unique<Cholmod>();
  const Epetra_CrsMatrix &k = K.trilinos_matrix(), &m = M.trilinos_matrix();
  const int n = k.NumMyRows();
  auto upper_row = [&](const Epetra_CrsMatrix &a, const int r, std::vector<std::pair<int, double>> &row) {
    int count = 0;
    double *values = nullptr;
    int *columns = nullptr;
    a.ExtractMyRowView(r, count, values, columns);
    const int i = a.RowMap().GID(r);
    row.clear();
    for (int c = 0; c < count; ++c)
      if (const int j = a.ColMap().GID(columns[c]); j >= i) row.emplace_back(j, values[c]);
    std::sort(row.begin(), row.end());
  };
  std::vector<std::pair<int, double>> row_k, row_m;
  std::size_t nnz = 0;
  for (int r = 0; r < n; ++r)
    {
      upper_row(k, r, row_k);
      nnz += row_k.size();
    }
  cholmod_sparse *L = cholmod_allocate_sparse(n, n, nnz, 1, 1, -1, CHOLMOD_REAL, &cholmod->common);
  auto *p = static_cast<int *>(L->p), *rows = static_cast<int *>(L->i);
  auto *x = static_cast<double *>(L->x);
  std::size_t next = 0;
  for (int r = 0; r < n; ++r)
    {
      const int i = k.RowMap().GID(r);
      p[i] = next;
      upper_row(k, r, row_k);
      upper_row(m, m.RowMap().LID(i), row_m);
      // M's pattern is K's (one sparsity pattern): merge the sorted rows.
      std::size_t c = 0;
      for (const auto &[j, value] : row_k)
        {
          double a = value;
          while (c < row_m.size() && row_m[c].first < j) ++c;
          if (c < row_m.size() && row_m[c].first == j) a -= sigma * row_m[c].second;
          rows[next] = j;
          x[next++] = a;
        }
    }
  p[n] = next;
  cholmod->factor = cholmod_analyze(L, &cholmod->common);
  cholmod_factorize(L, cholmod->factor, &cholmod->common);
  const bool positive_definite = cholmod->common.status == CHOLMOD_OK;
  cholmod_free_sparse(&L, &cholmod->common);
  if (!positive_definite)
    {
      cholmod.reset();
      return false;
    }
  cholmod->rhs = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &cholmod->common);
  return true;
}

void SparseFactorization::factorize_with_amesos(const std::string &method)
{
  Epetra_CrsMatrix &A = const_cast<Epetra_CrsMatrix &>(matrix.trilinos_matrix());
  const Epetra_Map &map = A.RowMap();
  lhs = std::make_unique<Epetra_Vector>(map);
  rhs = std::make_unique<Epetra_Vector>(map);
  problem = std::make_unique<Epetra_LinearProblem>(&A, lhs.get(), rhs.get());
  Amesos factory;
  const char *name = method == "mumps" ? "Amesos_Mumps" : "Amesos_Klu";
  solver.reset(factory.Create(name, *problem));
  if (!solver)
    throw SolverError(std::string("the sparse direct solver ") + name + " is not available in this Trilinos");
  Teuchos::ParameterList parameters;
  // The matrices here are symmetric: MUMPS then uses LDL^T, half the work and memory of LU.
  parameters.set("MatrixProperty", std::string("symmetric"));
  solver->SetParameters(parameters);
  if (solver->SymbolicFactorization() != 0 || solver->NumericFactorization() != 0)
    throw SolverError("the matrix could not be factorised: it is singular (a shift equal to an eigenvalue, or a "
                      "structure with a mechanism); change 'Modal analysis/Shift' or the supports");
}

SparseFactorization::~SparseFactorization() = default;

void SparseFactorization::solve(const double *b, double *x) const
{
  if (cholmod)
    {
      const std::size_t n = cholmod->rhs->nrow;
      std::copy(b, b + n, static_cast<double *>(cholmod->rhs->x));
      cholmod_dense *solution = cholmod_solve(CHOLMOD_A, cholmod->factor, cholmod->rhs, &cholmod->common);
      std::copy(static_cast<double *>(solution->x), static_cast<double *>(solution->x) + n, x);
      cholmod_free_dense(&solution, &cholmod->common);
      return;
    }
  const int n = rhs->MyLength();
  std::copy(b, b + n, &(*rhs)[0]);
  solver->Solve();
  std::copy(&(*lhs)[0], &(*lhs)[0] + n, x);
}

void SparseFactorization::solve_many(const double *B, double *X, const unsigned int k) const
{
  if (!cholmod)
    {
      const std::size_t n = rhs->MyLength();
      for (unsigned int j = 0; j < k; ++j) solve(B + j * n, X + j * n);
      return;
    }
  const std::size_t n = cholmod->rhs->nrow;
  cholmod_dense *many = cholmod_allocate_dense(n, k, n, CHOLMOD_REAL, &cholmod->common);
  std::copy(B, B + n * k, static_cast<double *>(many->x));
  cholmod_dense *solution = cholmod_solve(CHOLMOD_A, cholmod->factor, many, &cholmod->common);
  std::copy(static_cast<double *>(solution->x), static_cast<double *>(solution->x) + n * k, X);
  cholmod_free_dense(&solution, &cholmod->common);
  cholmod_free_dense(&many, &cholmod->common);
}
} // namespace flextrack::reduction
