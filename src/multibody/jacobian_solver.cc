// Epetra matrix of the DAE Jacobian, factorised by KLU or LAPACK's dense LU (jacobian_solver.h).
#include <multibody/jacobian_solver.h>
#include <multibody/system.h>

#include <Epetra_CrsGraph.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_Map.h>
#include <Epetra_SerialComm.h>

#include <klu.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace flextrack::multibody
{
struct JacobianSolver::Klu
{
  klu_common common;
  klu_symbolic *symbolic = nullptr;
  klu_numeric *numeric = nullptr;
  /// Reciprocal condition estimate (KLU's min |u_ii| / max |u_ii|) of the last factorisation
  /// with pivoting: a refactorisation far below it pivots afresh.
  double pivoted_rcond = 0, pivoted_rgrowth = 0; ///< and its reciprocal pivot growth
  Klu() { klu_defaults(&common); }
  ~Klu()
  {
    if (numeric) klu_free_numeric(&numeric, &common);
    if (symbolic) klu_free_symbolic(&symbolic, &common);
  }
};

double pattern_fill(const std::vector<std::vector<int>> &pattern)
{
  std::size_t entries = 0;
  for (const std::vector<int> &row : pattern) entries += row.size();
  const double n = pattern.size();
  return n > 0 ? entries / (n * n) : 0.0;
}

bool dense_factorisation_is_faster(const System &system, const std::vector<std::vector<int>> &pattern)
{
  const unsigned int n = system.size();
  if (n <= 5000 && pattern_fill(pattern) >= 0.3) return true;
  double blocks = 0;
  for (unsigned int b = 0; b < system.n_bodies(); ++b) blocks += std::pow(double(system.body(b).n_v()), 3);
  return n >= 1000 && 20 * blocks > std::pow(double(n), 3);
}

JacobianSolver::JacobianSolver(const std::vector<std::vector<int>> &pattern, const bool dense, const unsigned int n_condensed_)
  : n_condensed(dense ? n_condensed_ : 0)
{
  const int n = pattern.size();
  comm = std::make_unique<Epetra_SerialComm>();
  map = std::make_unique<Epetra_Map>(n, 0, *comm);
  std::vector<int> per_row(n);
  for (int i = 0; i < n; ++i) per_row[i] = pattern[i].size();
  graph = std::make_unique<Epetra_CrsGraph>(Copy, *map, per_row.data(), true);
  for (int i = 0; i < n; ++i)
    {
      std::vector<int> cols(pattern[i]);
      graph->InsertGlobalIndices(i, cols.size(), cols.data());
    }
  graph->FillComplete();
  graph->OptimizeStorage();
  A = std::make_unique<Epetra_CrsMatrix>(Copy, *graph);
  // Where each pattern entry lives in the matrix' value array, found once: Epetra's own
  // SumIntoGlobalValues maps every global index through the column map and searches the row
  // again at each call (8 % of the laser robot's integration with IDA, perf 2026-12-03). Up to
  // 1500 unknowns a table of all n^2 places (at most 9 MB) finds an entry in one load; above,
  // each row's columns are bisected.
  int *columns = nullptr;
  compressed_rows(row_start, columns, values);
  n_rows = n;
  if (n <= 1500)
    {
      slot_of.assign(std::size_t(n) * n, -1);
      for (int i = 0; i < n; ++i)
        for (int k = row_start[i]; k < row_start[i + 1]; ++k) slot_of[std::size_t(i) * n + A->ColMap().GID(columns[k])] = k;
    }
  else
    {
      entry_columns.resize(row_start[n]);
      entry_slots.resize(row_start[n]);
      for (int i = 0; i < n; ++i)
        {
          std::vector<std::pair<int, int>> row;
          for (int k = row_start[i]; k < row_start[i + 1]; ++k) row.emplace_back(A->ColMap().GID(columns[k]), k);
          std::sort(row.begin(), row.end());
          for (int k = row_start[i]; k < row_start[i + 1]; ++k) std::tie(entry_columns[k], entry_slots[k]) = row[k - row_start[i]];
        }
    }
  if (dense)
    dense_factors.resize(std::size_t(n) * n);
  else
    klu = std::make_unique<Klu>();
}

JacobianSolver::~JacobianSolver() = default;

void JacobianSolver::zero() { A->PutScalar(0.0); }

double &JacobianSolver::entry(const unsigned int row, const unsigned int col)
{
  if (row >= n_rows || col >= n_rows)
    throw std::logic_error("JacobianSolver: entry (" + std::to_string(row) + ", " + std::to_string(col) +
                           ") outside the " + std::to_string(n_rows) + " x " + std::to_string(n_rows) + " matrix");
  int slot = -1;
  if (!slot_of.empty())
    slot = slot_of[std::size_t(row) * n_rows + col];
  else
    {
      const int *first = entry_columns.data() + row_start[row], *last = entry_columns.data() + row_start[row + 1];
      const int *found = std::lower_bound(first, last, static_cast<int>(col));
      if (found != last && *found == static_cast<int>(col)) slot = entry_slots[found - entry_columns.data()];
    }
  if (slot < 0)
    throw std::logic_error("JacobianSolver: entry (" + std::to_string(row) + ", " + std::to_string(col) + ") outside the pattern");
  return values[slot];
}

void JacobianSolver::add(const std::vector<unsigned int> &rows, const std::vector<unsigned int> &cols, const double *block)
{
  // A block's exact zeros are skipped: a joint's block is about half zeros (its mu rows, the
  // velocity columns of its position rows), and adding them was a quarter of its Jacobian. An
  // entry outside the pattern is still refused where its value is not zero.
  const std::size_t n_cols = cols.size();
  for (std::size_t i = 0; i < rows.size(); ++i)
    {
      const double *row = block + i * n_cols;
      if (!slot_of.empty() && rows[i] < n_rows)
        {
          const int *slot = slot_of.data() + std::size_t(rows[i]) * n_rows;
          for (std::size_t k = 0; k < n_cols; ++k)
            if (row[k] != 0)
              {
                if (cols[k] < n_rows && slot[cols[k]] >= 0) values[slot[cols[k]]] += row[k];
                else entry(rows[i], cols[k]) += row[k]; // throws: outside the matrix or the pattern
              }
        }
      else
        for (std::size_t k = 0; k < n_cols; ++k)
          if (row[k] != 0) entry(rows[i], cols[k]) += row[k];
    }
}

void JacobianSolver::add(const unsigned int row, const unsigned int col, const double value)
{
  entry(row, col) += value;
}

void JacobianSolver::compressed_rows(int *&row_start, int *&columns, double *&values) const
{
  if (A->ExtractCrsDataPointers(row_start, columns, values) != 0)
    throw std::logic_error("JacobianSolver: the matrix' storage is not contiguous");
}

bool JacobianSolver::factorize_with_klu(const bool fresh_pivots)
{
  int *starts = nullptr, *columns = nullptr;
  double *entries = nullptr;
  compressed_rows(starts, columns, entries);
  const int n = map->NumMyElements();
  klu_common *common = &klu->common;
  if (!klu->symbolic)
    {
      klu->symbolic = klu_analyze(n, starts, columns, common);
      if (!klu->symbolic)
        throw std::runtime_error("KLU could not order the Jacobian (status " + std::to_string(common->status) + ")");
    }
  if (klu->numeric && !fresh_pivots)
    {
      // The last pivot order, if its pivots are still good: a pivot ratio (KLU's rcond, min |u_ii|
      // / max |u_ii|) or a reciprocal pivot growth (KLU's rgrowth, max |a| / max |u| per column)
      // that fell by more than 1e3 against the last pivoted factorisation means the old pivots
      // have become small or grow the factors, which then lose digits: pivot afresh.
      if (klu_refactor(starts, columns, entries, klu->symbolic, klu->numeric, common) &&
          klu_rcond(klu->symbolic, klu->numeric, common) && common->rcond > 1e-3 * klu->pivoted_rcond &&
          klu_rgrowth(starts, columns, entries, klu->symbolic, klu->numeric, common) &&
          common->rgrowth > 1e-3 * klu->pivoted_rgrowth)
        return true;
    }
  if (klu->numeric) klu_free_numeric(&klu->numeric, common);
  klu->numeric = klu_factor(starts, columns, entries, klu->symbolic, common);
  if (!klu->numeric) return false; // singular (KLU_SINGULAR), or out of memory
  klu_rcond(klu->symbolic, klu->numeric, common);
  klu_rgrowth(starts, columns, entries, klu->symbolic, klu->numeric, common);
  klu->pivoted_rcond = common->rcond;
  klu->pivoted_rgrowth = common->rgrowth;
  return true;
}

void copy_to_dense(const Epetra_CrsMatrix &A, std::vector<double> &column_major)
{
  const std::size_t n = A.NumMyRows();
  column_major.assign(n * n, 0.0);
  int *row_start = nullptr, *columns = nullptr;
  double *values = nullptr;
  if (A.ExtractCrsDataPointers(row_start, columns, values) != 0)
    throw std::logic_error("copy_to_dense: the matrix' storage is not contiguous");
  const int *row_gid = A.RowMap().MyGlobalElements(), *column_gid = A.ColMap().MyGlobalElements();
  for (std::size_t r = 0; r < n; ++r)
    for (int k = row_start[r]; k < row_start[r + 1]; ++k)
      column_major[std::size_t(column_gid[columns[k]]) * n + row_gid[r]] = values[k];
}

bool JacobianSolver::factorize_dense()
{
  copy_to_dense(*A, dense_factors);
  dense_factored = dense_lu.factorize(dense_factors.data(), map->NumMyElements(), n_condensed);
  if (dense_factored && dense_lu.condensed()) ++condensed_count;
  return dense_factored;
}

bool JacobianSolver::factorize(const bool fresh_pivots)
{
  ++count;
  if (klu) return factorize_with_klu(fresh_pivots);
  return factorize_dense();
}

void JacobianSolver::solve(const double *b, double *x)
{
  const int n = map->NumMyElements();
  if (klu)
    {
      // KLU factorised the compressed rows of A as columns, i.e. A^T: A x = b is its transposed solve.
      if (x != b) std::memcpy(x, b, n * sizeof(double)); // System::solve allows x == b
      if (!klu->numeric || !klu_tsolve(klu->symbolic, klu->numeric, n, 1, x, &klu->common))
        throw std::runtime_error("KLU could not solve with the Jacobian (status " + std::to_string(klu->common.status) + ")");
      return;
    }
  if (!dense_factored) throw std::runtime_error("the Jacobian was not factorised (singular) before a solve");
  if (x != b) std::memcpy(x, b, n * sizeof(double));
  dense_lu.solve(dense_factors.data(), x);
}
} // namespace flextrack::multibody
