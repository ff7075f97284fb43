// The LDL^T factorisation of a symmetric sparse matrix by MUMPS, called directly (Debian's
// libmumps), on the processes of the matrix's communicator.
//
// Why not through Trilinos Amesos: Amesos_Mumps (Trilinos 13.2) hands MUMPS the whole matrix as
// unsymmetric (SYM = 0, whatever "MatrixProperty" says), so MUMPS made an LU factor, about twice
// the memory and work of LDL^T, from two more copies of the matrix (a redistributed one and its
// triplets). Here each process hands MUMPS the upper triangle of its own rows (SYM = 2, symmetric
// indefinite, which also holds K - sigma M for a shift inside the spectrum), and the triplets are
// freed once the factor is made.
#pragma once

#include <cstddef>
#include <memory>

class Epetra_CrsMatrix;

namespace flextrack::reduction
{
class MumpsFactor
{
public:
  /// Analyses @p A (symmetric, rows distributed as its row map says): the ordering and the
  /// factor's size. Collective on A's communicator. SolverError if MUMPS fails. The solves
  /// gather at most @p host_numbers right-hand side entries on the first process at a time
  /// (2^24: two buffers of 128 MiB there).
  explicit MumpsFactor(const Epetra_CrsMatrix &A, std::size_t host_numbers = std::size_t(1) << 24);
  ~MumpsFactor();
  MumpsFactor(const MumpsFactor &) = delete;
  MumpsFactor &operator=(const MumpsFactor &) = delete;

  /// This process' memory for the factorisation in core, from the analysis [bytes].
  double estimated_bytes() const;
  /// The numerical factorisation (collective), once; A is not read afterwards. SolverError if A
  /// is singular or MUMPS runs out of memory.
  void factorize();
  /// X = A^{-1} B for @p k right-hand sides, each given as this process' rows of A (in the row
  /// map's order) and stored one after the other. Collective: every process calls it with the
  /// same k.
  void solve_many(const double *B, double *X, unsigned int k) const;
  /// The number of negative pivots of the LDL^T factor (INFOG(12)): by Sylvester's law of
  /// inertia, the number of negative eigenvalues of A, for A = K - sigma M the number of
  /// eigenvalues of (K, M) below sigma. Exact on one process; on several, MUMPS does not count
  /// the pivots of a root front that ScaLAPACK factorises.
  int negative_pivots() const;

private:
  /// solve_many for at most as many columns as the host's buffers are sized for.
  void solve_columns(const double *B, double *X, unsigned int k) const;
  struct Instance;
  std::unique_ptr<Instance> instance;
};
} // namespace flextrack::reduction
