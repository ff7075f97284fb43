#include <fem/csr_matrix.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>

#include <algorithm>
#include <stdexcept>

namespace flextrack::fem
{
CsrMatrix::CsrMatrix(std::vector<std::vector<int>> &&rows) : n_rows(rows.size())
{
  std::size_t total = 0;
  for (auto &r : rows)
    {
      std::sort(r.begin(), r.end());
      r.erase(std::unique(r.begin(), r.end()), r.end());
      total += r.size();
    }
  columns.reserve(total);
  for (auto &r : rows)
    {
      columns.insert(columns.end(), r.begin(), r.end());
      row_start.push_back(columns.size());
      std::vector<int>().swap(r);
    }
  values.assign(columns.size(), 0.0);
}

void CsrMatrix::add(const unsigned int row, const int column, const double v)
{
  const auto begin = columns.begin() + row_start[row], end = columns.begin() + row_start[row + 1];
  const auto it = std::lower_bound(begin, end, column);
  if (it == end || *it != column) throw std::logic_error("CsrMatrix::add: entry outside the pattern");
  values[it - columns.begin()] += v;
}

void CsrMatrix::to_trilinos(dealii::TrilinosWrappers::SparseMatrix &result) const
{
  to_trilinos(result, 0, n_rows, MPI_COMM_SELF);
}

void CsrMatrix::to_trilinos(dealii::TrilinosWrappers::SparseMatrix &result, const unsigned int first_row,
                            const unsigned int n_global, const MPI_Comm communicator) const
{
  const Epetra_MpiComm comm(communicator);
  const Epetra_Map map(static_cast<int>(n_global), static_cast<int>(n_rows), 0, comm);
  AssertThrow(map.MinMyGID() == static_cast<int>(first_row) || n_rows == 0,
              dealii::ExcMessage("the row blocks of a distributed matrix must follow the ranks"));
  std::vector<int> lengths(n_rows);
  for (unsigned int r = 0; r < n_rows; ++r) lengths[r] = row_start[r + 1] - row_start[r];
  Epetra_CrsMatrix A(Copy, map, lengths.data(), true);
  for (unsigned int r = 0; r < n_rows; ++r)
    if (lengths[r] > 0)
      A.InsertGlobalValues(first_row + r, lengths[r], values.data() + row_start[r], columns.data() + row_start[r]);
  A.FillComplete();
  result.reinit(A);
}

void CsrMatrix::to_trilinos_on_graph_of(const dealii::TrilinosWrappers::SparseMatrix &pattern,
                                        dealii::TrilinosWrappers::SparseMatrix &result, const unsigned int first_row) const
{
  result.reinit(pattern.trilinos_matrix(), false); // the graph shared (Epetra counts references), values zero
  auto &A = const_cast<Epetra_CrsMatrix &>(result.trilinos_matrix());
  for (unsigned int r = 0; r < n_rows; ++r)
    if (const int n = row_start[r + 1] - row_start[r]; n > 0)
      AssertThrow(A.ReplaceGlobalValues(static_cast<int>(first_row + r), n, values.data() + row_start[r],
                                        columns.data() + row_start[r]) == 0,
                  dealii::ExcMessage("an entry lies outside the shared pattern"));
}
} // namespace flextrack::fem
