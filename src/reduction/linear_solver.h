// Sparse direct solves (Trilinos Amesos, KLU) for static problems.
#pragma once

#include <deal.II/base/index_set.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

namespace flextrack::reduction
{
/// x = A^{-1} b.
dealii::Vector<double> solve_direct(const dealii::TrilinosWrappers::SparseMatrix &A, const dealii::Vector<double> &b);

/// Solve K u = f with u_i = values_i prescribed for i in @p prescribed (f is ignored there).
dealii::Vector<double> solve_with_prescribed_values(const dealii::TrilinosWrappers::SparseMatrix &K,
                                                    const dealii::IndexSet &prescribed,
                                                    const dealii::Vector<double> &values,
                                                    const dealii::Vector<double> &f = dealii::Vector<double>());
} // namespace flextrack::reduction
