// Linear static solutions K u = f of one FE model with fixed supports (at zero or at prescribed
// displacements), for many
// load vectors with one sparse factorisation.
//
// The model's stiffness is given without its supports (K_free); the supported dofs are taken out
// of a copy of it (rows and columns zeroed, the diagonal kept), which is factorised once by the
// project's SparseFactorization (CHOLMOD). K_free itself stays for the reactions
// r = K_free u - f at the supports and for the strain energy U = u^T K_free u / 2. Each solution
// is refined with residuals summed in long double (the reactions' balance needs it).
#pragma once

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <vector>

namespace flextrack::reduction
{
class SparseFactorization;

struct StaticSolution
{
  dealii::Vector<double> u;        ///< displacements (and rotations), zero at the supports
  dealii::Vector<double> reaction; ///< K_free u - f: support reactions (about 0 at free dofs)
  double strain_energy = 0;        ///< u^T K_free u / 2 [J]
  /// max |K_free u - f| over the free dofs, relative to the largest free-row entry of f and of the
  /// forces K_fs g of the prescribed support displacements g: the solve's accuracy.
  double residual = 0;
};

class StaticSolver
{
public:
  /// Factorises K_free with the dofs of @p supports fixed. SolverError if the supported
  /// structure is singular (a mechanism: too few supports).
  StaticSolver(const dealii::TrilinosWrappers::SparseMatrix &K_free, const dealii::AffineConstraints<double> &supports);
  ~StaticSolver();
  /// One solution per load vector @p f (full length; loads on supported dofs go to the reactions).
  /// @p prescribed: per load vector, the supported dofs' displacements (support settlements;
  /// values at free dofs are ignored); empty: all supports hold at zero. With prescribed values g
  /// the free dofs solve K_ff u_f = f_f - K_fs g.
  std::vector<StaticSolution> solve(const std::vector<dealii::Vector<double>> &f,
                                    const std::vector<dealii::Vector<double>> &prescribed = {}) const;

private:
  /// Refinement steps at most (each one solve and one product; stops when the residual stops falling).
  static constexpr unsigned int max_refinements = 3;
  /// K_free u - f, each row summed in long double.
  std::vector<long double> accurate_residual(const dealii::Vector<double> &u, const dealii::Vector<double> &f) const;

  const dealii::TrilinosWrappers::SparseMatrix &K;
  const dealii::AffineConstraints<double> &fixed;
  std::unique_ptr<SparseFactorization> factorization;
};
} // namespace flextrack::reduction
