// A sparse direct factorisation of a symmetric Trilinos matrix, solved many times (the
// shift-invert operator). Methods:
//  - "cholmod": supernodal Cholesky (SuiteSparse CHOLMOD) for positive definite matrices, the
//    case of every negative shift; if the matrix is not positive definite it falls back to MUMPS;
//  - "mumps": MUMPS's LDL^T (multifrontal, symmetric indefinite; reduction/mumps_factor.h), any
//    symmetric matrix, on the processes of the matrix;
//  - "klu": Trilinos Amesos KLU (LU), fine for small banded matrices.
#pragma once

#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <functional>
#include <memory>
#include <string>

class Amesos_BaseSolver;
class Epetra_LinearProblem;
class Epetra_Vector;

namespace flextrack::reduction
{
class MumpsFactor;

class SparseFactorization
{
public:
  /// Factorises A = K - sigma M (K and M share one sparsity pattern). @p method: "cholmod",
  /// "mumps" or "klu". The Cholesky path builds its input from K and M row by row, without an
  /// assembled copy of A. MUMPS reads a Trilinos copy of A (K itself for sigma = 0) until it
  /// has factorised it; KLU keeps that copy, or reads K, which must then outlive this object.
  /// Throws SolverError if A is singular.
  SparseFactorization(const dealii::TrilinosWrappers::SparseMatrix &K,
                      const dealii::TrilinosWrappers::SparseMatrix &M, double sigma, const std::string &method);
  /// The Cholesky factor of K with the dofs of @p fixed held: their rows and columns left out but
  /// for the diagonal (K_ii, or 1 where that is not positive), so that x = 0 there for b = 0
  /// there. No copy of K is made. SolverError if that matrix is not positive definite (a
  /// mechanism: the supports do not hold every rigid motion).
  SparseFactorization(const dealii::TrilinosWrappers::SparseMatrix &K, const std::vector<bool> &fixed);
  /// The Cholesky factor of A = K - sigma M in the least memory: @p release is called as soon as
  /// CHOLMOD's copy of A is built, before the factorisation, so that the caller frees K and M
  /// there (they are not touched afterwards). SolverError (out of memory, or A not positive
  /// definite) if that fails: there is no fallback to another method, since K and M may be gone.
  SparseFactorization(const dealii::TrilinosWrappers::SparseMatrix &K,
                      const dealii::TrilinosWrappers::SparseMatrix &M, double sigma,
                      const std::function<void()> &release);
  ~SparseFactorization();
  /// x = A^{-1} b for arrays of this process' rows of A (all of A.m() on one process).
  void solve(const double *b, double *x) const;
  /// X = A^{-1} B for @p k right-hand sides stored column by column (this process' rows of A
  /// each); CHOLMOD and MUMPS solve them together (level-3 BLAS), several times faster than one
  /// by one.
  void solve_many(const double *B, double *X, unsigned int k) const;

  /// Whether A = P^T L L^T P is available in its halves (a supernodal Cholesky factor, which
  /// large models get): then an eigen solve can work on the symmetric standard problem
  /// L^{-1} P M P^T L^{-T} y = y / (lambda - sigma), which needs one product with M per step
  /// instead of the about three of the generalised one (its M-inner products).
  bool has_halves() const;
  /// The size of the factor (and, for Cholesky, its input) on this process, estimated from the
  /// analysis before the factorisation [bytes]; 0 for KLU, which does not say.
  double memory_estimate_bytes() const { return estimated_bytes; }
  /// This process' resident memory when the factorisation started [bytes]: what it held besides.
  double resident_bytes_before() const { return resident_before; }
  /// Y = L^{-1} P B for @p k columns stored one after the other (has_halves() only).
  void solve_lower(const double *B, double *Y, unsigned int k = 1) const;
  /// X = P^T L^{-T} Y for @p k columns stored one after the other (has_halves() only): one pass
  /// over the factor for all of them.
  void solve_upper(const double *Y, double *X, unsigned int k = 1) const;

private:
  // Members are destroyed in reverse order: the solver before the problem, vectors and matrix
  // it refers to.
  dealii::TrilinosWrappers::SparseMatrix matrix; // A for KLU (empty for sigma = 0, and after MUMPS)
  std::unique_ptr<Epetra_LinearProblem> problem;
  std::unique_ptr<Epetra_Vector> lhs, rhs;
  std::unique_ptr<Amesos_BaseSolver> solver; // KLU
  std::unique_ptr<MumpsFactor> mumps;
  struct Cholmod;
  std::unique_ptr<Cholmod> cholmod;
  bool out_of_memory = false; ///< why the last Cholesky factorisation failed, if it did
  double estimated_bytes = 0, resident_before = 0;
  /// Cholesky of A; false if A is not positive definite.
  bool factorize_with_cholmod(const dealii::TrilinosWrappers::SparseMatrix &K,
                              const dealii::TrilinosWrappers::SparseMatrix &M, double sigma,
                              const std::vector<bool> *fixed = nullptr,
                              const std::function<void()> &release = {});
  /// LU of @p a by KLU (Trilinos Amesos); @p a must outlive this object.
  void factorize_with_klu(const dealii::TrilinosWrappers::SparseMatrix &a);
  /// LDL^T of @p a by MUMPS, after a memory check on every process of @p a.
  void factorize_with_mumps(const dealii::TrilinosWrappers::SparseMatrix &a);
};
} // namespace flextrack::reduction
