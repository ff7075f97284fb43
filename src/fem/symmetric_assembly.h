// The two steps every FE model here ends its stiffness and mass assembly with (arms and solids
// alike): symmetric cell matrices added through the supports, and the supported rows of M
// zeroed, so that supported dofs have infinite eigenvalues and never appear among the lowest
// modes.
#pragma once

#include <deal.II/base/types.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <vector>

namespace flextrack::fem
{
/// Cell matrices integrated on their lower triangle (j <= i) only: mirrors both to the upper
/// triangle, then adds them to @p K and @p M through @p applied (the supports, or no constraint).
/// An empty @p M (0 rows: a model without mass, e.g. for statics) is left alone, here and below.
void add_symmetric_cell_matrices(dealii::FullMatrix<double> &k_cell, dealii::FullMatrix<double> &m_cell,
                                 const std::vector<dealii::types::global_dof_index> &cell_dofs,
                                 const dealii::AffineConstraints<double> &applied,
                                 dealii::TrilinosWrappers::SparseMatrix &K, dealii::TrilinosWrappers::SparseMatrix &M);

/// After the cell loop: compresses @p K and @p M and sets M's diagonal to zero at the dofs that
/// @p applied constrains (K keeps its positive diagonal there), on the locally owned rows.
void finish_assembly(const dealii::AffineConstraints<double> &applied, dealii::TrilinosWrappers::SparseMatrix &K,
                     dealii::TrilinosWrappers::SparseMatrix &M);
} // namespace flextrack::fem
