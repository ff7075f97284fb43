#include <base/large_pages.h>
#include <base/memory.h>
#include <base/solver_error.h>
#include <reduction/modal_solver.h>
#include <reduction/mumps_factor.h>
#include <reduction/sparse_factorization.h>
#include <reduction/supernode_width.h>

#include <Amesos.h>
#include <Amesos_BaseSolver.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_MpiComm.h>
#include <Epetra_Vector.h>
#include <cholmod.h>

#include <algorithm>
#include <new>
#include <numeric>
#include <vector>

namespace flextrack::reduction
{
struct SparseFactorization::Cholmod
{
  cholmod_common common;
  cholmod_factor *factor = nullptr;
  cholmod_dense *rhs = nullptr;
  /// A large (supernodal) factor is of P A P^T, permuted here: row p of it is row order[p] of
  /// A. Empty: CHOLMOD permutes a small (simplicial) factor itself.
  std::vector<int> order;
  Cholmod()
  {
    // The factor of a large body is the largest array of a reduction: on 2 MiB pages
    // (base/large_pages.h). SuiteSparse's allocator is process-wide; this only adds advice.
    SuiteSparse_config.malloc_func = base::malloc_on_large_pages;
    SuiteSparse_config.calloc_func = base::calloc_on_large_pages;
    cholmod_start(&common);
    common.print = 0; // a matrix that is not positive definite is reported by the caller, not on stderr
  }
  /// X = S B for @p k columns (one after the other) with CHOLMOD's system @p system (S: L^{-1},
  /// L^{-T} or A^{-1} of the factor), B's rows taken in the factor's order if @p permute_in
  /// (row p of the factor's system is row order[p]), X's rows put back if @p permute_out.
  void solve(const int system, const double *B, double *X, const unsigned int k, const bool permute_in,
             const bool permute_out)
  {
    const std::size_t n = rhs->nrow;
    auto row = [&](const std::size_t p) -> std::size_t { return order.empty() ? p : order[p]; };
    cholmod_dense *many = k == 1 ? rhs : cholmod_allocate_dense(n, k, n, CHOLMOD_REAL, &common);
    if (!many) throw std::bad_alloc();
    auto *in = static_cast<double *>(many->x);
    for (std::size_t c = 0; c < k; ++c)
      for (std::size_t p = 0; p < n; ++p) in[c * n + p] = B[c * n + (permute_in ? row(p) : p)];
    cholmod_dense *solution = cholmod_solve(system, factor, many, &common);
    if (many != rhs) cholmod_free_dense(&many, &common);
    if (!solution) throw std::bad_alloc();
    const auto *out = static_cast<const double *>(solution->x);
    for (std::size_t c = 0; c < k; ++c)
      for (std::size_t p = 0; p < n; ++p) X[c * n + (permute_out ? row(p) : p)] = out[c * n + p];
    cholmod_free_dense(&solution, &common);
  }
  ~Cholmod()
  {
    if (factor) cholmod_free_factor(&factor, &common);
    if (rhs) cholmod_free_dense(&rhs, &common);
    cholmod_finish(&common);
  }
};

namespace
{
SolverError out_of_memory_error(const std::size_t n_dofs)
{
  return SolverError("out of memory in the Cholesky factorisation (" + std::to_string(n_dofs) +
                     " dofs); use a coarser mesh or a computer with more memory");
}
} // namespace

SparseFactorization::SparseFactorization(const dealii::TrilinosWrappers::SparseMatrix &K,
                                         const dealii::TrilinosWrappers::SparseMatrix &M, const double sigma,
                                         const std::string &method)
{
  if (method == "cholmod" && factorize_with_cholmod(K, M, sigma))
    return;
  if (out_of_memory) throw out_of_memory_error(K.m()); // MUMPS would need more
  // Not positive definite (a positive shift), or another method asked for: LDL^T or LU. With
  // sigma = 0 (a distributed reduction's body, clamped or not) A is K itself: no copy, which
  // would be one more matrix the size of K on every process, beside the factor; K must then
  // outlive this object (the header says so).
  if (sigma != 0)
    {
      matrix.copy_from(K);
      matrix.add(-sigma, M);
    }
  if (method == "klu")
    factorize_with_klu(sigma != 0 ? matrix : K);
  else
    {
      factorize_with_mumps(sigma != 0 ? matrix : K);
      matrix.clear(); // MUMPS holds its factor and does not read A again
    }
}

SparseFactorization::SparseFactorization(const dealii::TrilinosWrappers::SparseMatrix &K,
                                         const std::vector<bool> &fixed)
{
  if (factorize_with_cholmod(K, K, 0.0, &fixed)) return;
  if (out_of_memory) throw out_of_memory_error(K.m());
  throw SolverError("the stiffness matrix with these supports is singular: either the supports do not hold the "
                    "structure against every rigid motion (a mechanism; add supports), or the elements have "
                    "zero-energy modes of their own (e.g. 'Solid/Integration = reduced' on a mesh with one cell "
                    "across; use 'full')");
}

SparseFactorization::SparseFactorization(const dealii::TrilinosWrappers::SparseMatrix &K,
                                         const dealii::TrilinosWrappers::SparseMatrix &M, const double sigma,
                                         const std::function<void()> &release)
{
  const auto n = K.m(); // K is empty after release()
  if (factorize_with_cholmod(K, M, sigma, nullptr, release)) return;
  if (out_of_memory) throw out_of_memory_error(n);
  // With sigma < 0, K - sigma M = K + |sigma| M is positive definite unless the elements have
  // zero-energy modes that carry no mass either, or the shift is far below the spectrum.
  throw SolverError("K - sigma M is not positive definite (sigma = " + std::to_string(sigma) +
                    " rad^2/s^2): the elements may have zero-energy modes (e.g. 'Solid/Integration = reduced'); "
                    "use full integration, or set 'Modal analysis/Shift' nearer the lowest frequency squared");
}

namespace
{
/// The widest supernode kept (cap_supernode_width): on the 7.4e4-dof block of the benchmark, 256
/// columns cut the factor from 59.0 to 53.1 million numbers (and CHOLMOD's largest update
/// workspace from 1.8 to 0.45 million) for 2.7 % of the run's time (each piece updates its
/// ancestors on its own); 128 saves 1.3 million more numbers but costs about 9 % of the eigen
/// solve's time, as BLAS works on narrower panels (doc/benchmarks.md).
constexpr std::size_t max_supernode_width = 256;

/// Calls @p use(i, j, a_ij) for every stored entry of the upper triangle (j >= i) of
/// A = K - sigma M, by global indices, in no particular order within a row. M's pattern lies in
/// K's (one sparsity pattern); M's row is scattered into @p scratch (n zeros on entry and exit).
/// With @p fixed, the rows and columns of fixed dofs are left out but for their diagonal (kept
/// if positive, 1 otherwise).
template <typename Use>
void for_each_upper_entry(const Epetra_CrsMatrix &k, const Epetra_CrsMatrix &m, const double sigma,
                          std::vector<double> &scratch, const std::vector<bool> *fixed, Use &&use)
{
  for (int r = 0; r < k.NumMyRows(); ++r)
    {
      const int i = k.RowMap().GID(r);
      int count = 0;
      double *values = nullptr;
      int *columns = nullptr;
      if (sigma != 0)
        {
          m.ExtractMyRowView(m.RowMap().LID(i), count, values, columns);
          for (int c = 0; c < count; ++c) scratch[m.ColMap().GID(columns[c])] = values[c];
        }
      const int n_m = count;
      const int *m_columns = columns;
      k.ExtractMyRowView(r, count, values, columns);
      for (int c = 0; c < count; ++c)
        if (const int j = k.ColMap().GID(columns[c]); j >= i)
          {
            const double a = values[c] - sigma * scratch[j];
            if (!fixed)
              use(i, j, a);
            else if (i == j)
              use(i, j, (*fixed)[i] && !(a > 0) ? 1.0 : a);
            else if (!(*fixed)[i] && !(*fixed)[j])
              use(i, j, a);
          }
      for (int c = 0; c < n_m; ++c) scratch[m.ColMap().GID(m_columns[c])] = 0;
    }
}
/// Sorts the rows within each column of @p A (CHOLMOD's sorted input); a column holds tens of
/// entries.
void sort_columns(cholmod_sparse *A)
{
  auto *start = static_cast<int *>(A->p), *rows = static_cast<int *>(A->i);
  auto *values = static_cast<double *>(A->x);
  std::vector<std::pair<int, double>> column;
  for (std::size_t j = 0; j < A->ncol; ++j)
    {
      column.clear();
      for (int e = start[j]; e < start[j + 1]; ++e) column.emplace_back(rows[e], values[e]);
      std::sort(column.begin(), column.end());
      for (std::size_t e = 0; e < column.size(); ++e)
        {
          rows[start[j] + e] = column[e].first;
          values[start[j] + e] = column[e].second;
        }
    }
  A->sorted = true;
}
} // namespace

bool SparseFactorization::factorize_with_cholmod(const dealii::TrilinosWrappers::SparseMatrix &K,
                                                 const dealii::TrilinosWrappers::SparseMatrix &M, const double sigma,
                                                 const std::vector<bool> *fixed,
                                                 const std::function<void()> &release)
{
  // Memory is the limit of large eigen solves (the factor is most of it), so CHOLMOD gets A
  // once: first the fill-reducing ordering P from A's pattern alone, then A already permuted,
  // P A P^T, as the lower triangle in compressed columns. CHOLMOD factorises such a matrix in
  // its natural order in place; handed an unpermuted A it would make a permuted copy for the
  // whole factorisation (and two transposes on the way).
  cholmod = std::make_unique<Cholmod>();
  auto &common = cholmod->common;
  const Epetra_CrsMatrix &k = K.trilinos_matrix(), &m = M.trilinos_matrix();
  const int n = k.NumMyRows();
  std::vector<double> scratch(n, 0.0);
  std::vector<int> count(n + 1, 0);
  // Column j of the lower triangle of A (or of P A P^T) = the upper part of row j, in the new
  // numbering: entry (i, j) goes to column min(new i, new j), row max(...). Two passes: count, fill.
  auto compressed_columns = [&](const std::vector<int> &new_index, const int xtype) {
    std::fill(count.begin(), count.end(), 0);
    std::size_t nnz = 0;
    for_each_upper_entry(k, m, 0.0, scratch, fixed, [&](int i, int j, double) {
      ++count[std::min(new_index[i], new_index[j])];
      ++nnz;
    });
    cholmod_sparse *A = cholmod_allocate_sparse(n, n, nnz, false, true, -1, xtype, &common);
    auto *start = static_cast<int *>(A->p), *rows = static_cast<int *>(A->i);
    auto *values = static_cast<double *>(A->x);
    start[0] = 0;
    for (int j = 0; j < n; ++j) start[j + 1] = start[j] + count[j];
    std::copy(start, start + n, count.begin()); // next free place in each column
    for_each_upper_entry(k, m, values ? sigma : 0.0, scratch, fixed, [&](int i, int j, double a) {
      const int a_i = new_index[i], a_j = new_index[j];
      const int place = count[std::min(a_i, a_j)]++;
      rows[place] = std::max(a_i, a_j);
      if (values) values[place] = a;
    });
    return A;
  };

  std::vector<int> identity(n);
  std::iota(identity.begin(), identity.end(), 0);
  cholmod_sparse *pattern = compressed_columns(identity, CHOLMOD_PATTERN);
  // Sorted columns: the orderings break ties by position, and should see A as before (Epetra's
  // local column order need not be the global one).
  cholmod_sort(pattern, &common);
  const double entries_of_A = static_cast<double>(cholmod_nnz(pattern, &common));
  cholmod_factor *symbolic = cholmod_analyze(pattern, &common); // AMD or METIS, postordered
  base::probe_memory("fill-reducing ordering done");
  cholmod_free_sparse(&pattern, &common);
  if (!symbolic) throw SolverError("CHOLMOD could not order the matrix (out of memory?)");
  // The factor's numbers (8 bytes each) and A's entries (value and row index), known from the
  // ordering: a factor that cannot fit is refused before A is built, once the ordering's
  // workspace is given back, before the machine starts to swap.
  estimated_bytes = 8.0 * (symbolic->is_super ? static_cast<double>(symbolic->xsize) : common.lnz) + 12.0 * entries_of_A;
  auto check_memory = [&]() {
    resident_before = base::resident_bytes();
    base::check_memory_for("the Cholesky factorisation of the " + std::to_string(n) + "-dof matrix", estimated_bytes);
  };
  cholmod_sparse *A = nullptr;
  if (symbolic->is_super)
    {
      cholmod->order.assign(static_cast<int *>(symbolic->Perm), static_cast<int *>(symbolic->Perm) + n);
      cholmod_free_factor(&symbolic, &common);
      base::release_free_heap(); // the ordering's workspace, before A and the factor
      check_memory();
      std::vector<int> new_index(n);
      for (int p = 0; p < n; ++p) new_index[cholmod->order[p]] = p;
      A = compressed_columns(new_index, CHOLMOD_REAL);
      sort_columns(A);
      common.nmethods = 1;
      common.method[0].ordering = CHOLMOD_NATURAL;
      common.postorder = false; // the order above is postordered already
      cholmod->factor = cholmod_analyze(A, &common);
      if (cholmod->factor)
        {
          try
            {
              cap_supernode_width(*cholmod->factor, max_supernode_width, common);
            }
          catch (const std::bad_alloc &)
            {
              cholmod_free_factor(&cholmod->factor, &common);
              common.status = CHOLMOD_OUT_OF_MEMORY; // reported below
            }
        }
    }
  else
    {
      // A small factor (simplicial LDL^T): memory does not matter, and CHOLMOD permutes A
      // itself, as it always has here, which keeps these results as they were to the last bit
      // (the row-by-row factorisation sums in another order on a pre-permuted matrix).
      cholmod->factor = symbolic; // freed with cholmod if the check below throws
      check_memory();
      A = compressed_columns(identity, CHOLMOD_REAL);
      sort_columns(A);
    }
  if (release)
    {
      release(); // K and M: from here on only CHOLMOD's A and factor are needed
      base::release_free_heap();
    }
  if (cholmod->factor) cholmod_factorize(A, cholmod->factor, &common);
  base::probe_memory("Cholesky factor of A made");
  const bool positive_definite = cholmod->factor && common.status == CHOLMOD_OK;
  out_of_memory = common.status == CHOLMOD_OUT_OF_MEMORY;
  cholmod_free_sparse(&A, &common);
  base::release_free_heap(); // A's pages, before the solves
  base::probe_memory("A freed");
  if (!positive_definite)
    {
      cholmod.reset();
      return false;
    }
  cholmod->rhs = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &common);
  return true;
}

void SparseFactorization::factorize_with_klu(const dealii::TrilinosWrappers::SparseMatrix &a)
{
  // Amesos takes a non-const matrix; it only reads it.
  Epetra_CrsMatrix &A = const_cast<Epetra_CrsMatrix &>(a.trilinos_matrix());
  const Epetra_Map &map = A.RowMap();
  lhs = std::make_unique<Epetra_Vector>(map);
  rhs = std::make_unique<Epetra_Vector>(map);
  problem = std::make_unique<Epetra_LinearProblem>(&A, lhs.get(), rhs.get());
  Amesos factory;
  solver.reset(factory.Create("Amesos_Klu", *problem));
  if (!solver) throw SolverError("the sparse direct solver Amesos_Klu is not available in this Trilinos");
  const bool analysed = solver->SymbolicFactorization() == 0;
  if (!analysed || solver->NumericFactorization() != 0)
    throw SolverError("the matrix could not be factorised: it is singular (a shift equal to an eigenvalue, or a "
                      "structure with a mechanism); change 'Modal analysis/Shift' or the supports");
}

void SparseFactorization::factorize_with_mumps(const dealii::TrilinosWrappers::SparseMatrix &a)
{
  const Epetra_CrsMatrix &A = a.trilinos_matrix();
  mumps = std::make_unique<MumpsFactor>(A);
  base::probe_memory("MUMPS analysis done");
  // MUMPS's estimate from its analysis, on this process; every process of the matrix checks its
  // machine before the factorisation is started.
  estimated_bytes = mumps->estimated_bytes();
  resident_before = base::resident_bytes();
  const MPI_Comm communicator = dynamic_cast<const Epetra_MpiComm &>(A.Comm()).Comm();
  base::check_memory_for("the LDL^T factorisation (MUMPS) of the " + std::to_string(A.NumGlobalRows64()) +
                           "-dof matrix",
                         estimated_bytes, &communicator);
  mumps->factorize();
}

SparseFactorization::~SparseFactorization() = default;

void SparseFactorization::solve(const double *b, double *x) const
{
  if (cholmod || mumps)
    {
      solve_many(b, x, 1);
      return;
    }
  const int n = rhs->MyLength();
  std::copy(b, b + n, &(*rhs)[0]);
  solver->Solve();
  std::copy(&(*lhs)[0], &(*lhs)[0] + n, x);
}

bool SparseFactorization::has_halves() const
{
  return cholmod && !cholmod->order.empty() && cholmod->factor->is_ll;
}

void SparseFactorization::solve_lower(const double *B, double *Y, const unsigned int k) const
{
  // The factor is of P A P^T, analysed in CHOLMOD's natural order: CHOLMOD permutes only for
  // its systems P, Pt and A of a factor in another order, so P is applied here.
  cholmod->solve(CHOLMOD_L, B, Y, k, true, false);
}

void SparseFactorization::solve_upper(const double *Y, double *X, const unsigned int k) const
{
  cholmod->solve(CHOLMOD_Lt, Y, X, k, false, true);
}

void SparseFactorization::solve_many(const double *B, double *X, const unsigned int k) const
{
  if (mumps)
    {
      mumps->solve_many(B, X, k);
      return;
    }
  if (!cholmod)
    {
      const std::size_t n = rhs->MyLength();
      for (unsigned int j = 0; j < k; ++j) solve(B + j * n, X + j * n);
      return;
    }
  // (P A P^T)^{-1} applied to P b, then permuted back (P = I where CHOLMOD permutes itself).
  cholmod->solve(CHOLMOD_A, B, X, k, true, true);
}
} // namespace flextrack::reduction
