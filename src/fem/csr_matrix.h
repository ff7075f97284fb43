// A serial sparse matrix in compressed-row form, built row by row with sorted, unique columns,
// and turned into a Trilinos matrix with every row inserted exactly once into storage of the
// exact size (Epetra's incremental insertion reallocates and is quadratic in the row length).
#pragma once

#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <vector>

namespace flextrack::fem
{
struct CsrMatrix
{
  unsigned int n_rows = 0;
  std::vector<unsigned int> row_start{0}; ///< n_rows + 1
  std::vector<int> columns;               ///< sorted within each row
  std::vector<double> values;

  /// Builds the pattern from per-row column lists (sorted and made unique here); values zero.
  explicit CsrMatrix(std::vector<std::vector<int>> &&rows);
  CsrMatrix() = default;
  /// Adds @p v at (row, column), which must be in the pattern.
  void add(unsigned int row, int column, double v);
  /// The same matrix in @p result (serial, on MPI_COMM_SELF).
  void to_trilinos(dealii::TrilinosWrappers::SparseMatrix &result) const;
  /// These rows as rows first_row ... first_row + n_rows - 1 of a square matrix of
  /// @p n_global rows distributed over @p communicator (each process passes its own block; the
  /// blocks follow each other in the order of the ranks).
  void to_trilinos(dealii::TrilinosWrappers::SparseMatrix &result, unsigned int first_row, unsigned int n_global,
                   MPI_Comm communicator) const;
  /// A matrix of this pattern and these values that shares the graph (column indices) of
  /// @p pattern, whose pattern holds this one's (rows first_row ... of it): the second of two
  /// matrices of one pattern (K and M) costs its values only.
  void to_trilinos_on_graph_of(const dealii::TrilinosWrappers::SparseMatrix &pattern,
                               dealii::TrilinosWrappers::SparseMatrix &result, unsigned int first_row = 0) const;
};
} // namespace flextrack::fem
