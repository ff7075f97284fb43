// Linear static solutions K u = f of one FE model with fixed supports (at zero or at prescribed
// displacements), for many
// load vectors with one sparse factorisation.
//
// The model's stiffness is given without its supports (K_free); the supported dofs' rows and
// columns are left out (the diagonal kept) of the matrix that the project's SparseFactorization
// (CHOLMOD) factorises once, built from K_free's rows without a copy of K; or, for solids too
// large for a factor, K with the supports applied is solved by conjugate gradients with an
// algebraic multigrid preconditioner (StaticSolverSettings::iterative). K_free itself stays for the reactions
// r = K_free u - f at the supports and for the strain energy U = u^T K_free u / 2. Each solution
// is refined with residuals summed in long double (the reactions' balance needs it).
#pragma once

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <functional>
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

/// A u with every row's sum accumulated in long double (64-bit mantissa on x86): the terms
/// A_ij u_j of a bending solution are 1e4..1e6 times their sum, so a double sum loses the digits
/// that reactions and refinement need.
std::vector<long double> long_double_product(const dealii::TrilinosWrappers::SparseMatrix &A,
                                             const std::vector<long double> &u);

/// How the supported system is solved.
struct StaticSolverSettings
{
  /// false: the sparse Cholesky factor (CHOLMOD), exact to round-off, one factor for every load
  /// case. true: conjugate gradients preconditioned by smoothed-aggregation algebraic multigrid
  /// (Trilinos ML), for solids too large for the factor's memory; every case its own iteration.
  bool iterative = false;
  /// Iterative: each CG solve stops at |r| <= tolerance |b| (2-norms over the free rows).
  double tolerance = 1e-10;
  /// Iterative: the rigid motions of the unsupported structure, the multigrid's near-null space
  /// (without them aggregation-based AMG converges slowly on elasticity).
  std::vector<dealii::Vector<double>> rigid_modes;
  /// Iterative: CG iterations per solve at most (SolverError beyond).
  unsigned int max_iterations = 5000;
  /// Optional: the model's internal forces K u for a long-double u, summed so that rigid motions
  /// give no net force (fem::SolidModel::internal_forces); used for the residuals of the
  /// refinement and the reactions instead of the assembled K (costs one assembly each).
  std::function<std::vector<long double>(const std::vector<long double> &)> internal_forces;
};

class StaticSolver
{
public:
  /// Factorises K_free with the dofs of @p supports fixed (or, iterative, builds the multigrid
  /// hierarchy). SolverError if the supported structure is singular (a mechanism: too few
  /// supports).
  StaticSolver(const dealii::TrilinosWrappers::SparseMatrix &K_free, const dealii::AffineConstraints<double> &supports,
               StaticSolverSettings settings = {});
  ~StaticSolver();
  /// One solution per load vector @p f (full length; loads on supported dofs go to the reactions).
  /// @p prescribed: per load vector, the supported dofs' displacements (support settlements;
  /// values at free dofs are ignored); empty: all supports hold at zero. With prescribed values g
  /// the free dofs solve K_ff u_f = f_f - K_fs g.
  std::vector<StaticSolution> solve(const std::vector<dealii::Vector<double>> &f,
                                    const std::vector<dealii::Vector<double>> &prescribed = {}) const;

  /// CG iterations summed over every solve so far (0 for the direct solver).
  unsigned int iterations() const { return cg_iterations; }

private:
  /// Iterative: SolverError if the supports leave a rigid motion free (the factor finds that itself).
  void refuse_mechanism() const;
  /// x = A^{-1} b for @p k right-hand sides (columns of length n), A the supported K.
  void solve_supported(const double *b, double *x, std::size_t k) const;
  /// Refinement steps at most (each one solve and one product; stops when the residual stops falling).
  static constexpr unsigned int max_refinements = 3;
  /// K_free u - f, each row summed in long double.
  std::vector<long double> accurate_residual(const std::vector<long double> &u, const dealii::Vector<double> &f) const;

  const dealii::TrilinosWrappers::SparseMatrix &K;
  const dealii::AffineConstraints<double> &fixed;
  StaticSolverSettings settings;
  std::unique_ptr<SparseFactorization> factorization;
  std::unique_ptr<dealii::TrilinosWrappers::SparseMatrix> supported; ///< iterative: A itself
  /// The rigid modes, one after the other; ML keeps a pointer to them, so they are declared
  /// (and destroyed) before (after) the multigrid.
  std::vector<double> null_space;
  std::unique_ptr<dealii::TrilinosWrappers::PreconditionAMG> multigrid;
  mutable unsigned int cg_iterations = 0;
};
} // namespace flextrack::reduction
