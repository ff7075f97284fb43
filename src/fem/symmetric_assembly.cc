#include <fem/symmetric_assembly.h>

namespace flextrack::fem
{
using namespace dealii;

void add_symmetric_cell_matrices(FullMatrix<double> &k_cell, FullMatrix<double> &m_cell,
                                 const std::vector<types::global_dof_index> &cell_dofs,
                                 const AffineConstraints<double> &applied, TrilinosWrappers::SparseMatrix &K,
                                 TrilinosWrappers::SparseMatrix &M)
{
  for (unsigned int i = 0; i < k_cell.m(); ++i)
    for (unsigned int j = 0; j < i; ++j)
      {
        k_cell(j, i) = k_cell(i, j);
        m_cell(j, i) = m_cell(i, j);
      }
  applied.distribute_local_to_global(k_cell, cell_dofs, K);
  if (M.m() > 0) applied.distribute_local_to_global(m_cell, cell_dofs, M);
}

void finish_assembly(const AffineConstraints<double> &applied, TrilinosWrappers::SparseMatrix &K,
                     TrilinosWrappers::SparseMatrix &M)
{
  K.compress(VectorOperation::add);
  if (M.m() == 0) return; // a stiffness-only model
  M.compress(VectorOperation::add);
  for (const auto i : M.locally_owned_range_indices())
    if (applied.is_constrained(i)) M.set(i, i, 0.0);
  M.compress(VectorOperation::insert);
}
} // namespace flextrack::fem
