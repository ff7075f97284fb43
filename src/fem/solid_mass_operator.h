// The consistent mass matrix of a solid applied cell by cell, y = M x, without assembling M.
//
// Why: the eigen solve of a large solid is limited by memory, and the Cholesky factor of
// K - sigma M is most of it. The Lanczos iteration needs M only as a product; the cells' mass
// matrices hold that product in a small fraction of an assembled M (a hex20 cell: the 20 x 20
// scalar matrix int rho N_a N_b, 210 numbers for its 60 x 60 block, against 60 x 60 couplings
// of an assembled row block with their column indices), so K and M can be freed before the
// factorisation (reduction/modal_solver.h, lowest_modes_releasing_matrices).
//
// The element is vector-valued with one scalar shape function per component (FESystem of
// three equal elements), so a cell's mass block is the scalar matrix m_ab = int rho N_a N_b dx
// on each component, zero across components. The supported dofs (held) get zero rows and
// columns, as in the assembled, supported M (fem/symmetric_assembly.h). The product equals the
// assembled one to round-off (the sums run in another order).
#pragma once

#include <deal.II/base/quadrature.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>

#include <cstddef>
#include <vector>

namespace flextrack::fem
{
class SolidMassOperator
{
public:
  /// The mass matrices of every active cell of @p dofs (a three-component element) on
  /// @p mapping, integrated with @p rule, density @p rho [kg/m^3]; @p held: per dof, true where
  /// a support fixes it (empty: nothing held).
  SolidMassOperator(const dealii::DoFHandler<3> &dofs, const dealii::Mapping<3> &mapping,
                    const dealii::Quadrature<3> &rule, double rho, std::vector<bool> held);

  /// y = M x, both of n() entries, y overwritten; x and y must not overlap.
  void vmult(const double *x, double *y) const;
  std::size_t n() const { return n_dofs; }
  /// Bytes held (cell matrices and dof indices).
  std::size_t memory_consumption() const;

private:
  std::size_t n_dofs;
  unsigned int n_scalar; ///< scalar shape functions per cell (20 for hex20)
  std::vector<bool> held;
  /// Per cell, the dof of scalar function a and component c at [cell][a][c].
  std::vector<dealii::types::global_dof_index> cell_dofs;
  /// Per cell, the lower triangle of m_ab row by row (b <= a), [kg].
  std::vector<double> cell_masses;
};
} // namespace flextrack::fem
