// The sparse Jacobian of the DAE and its direct solver: an Epetra_CrsMatrix on an
// Epetra_SerialComm (serial, so `flextrack run` needs no MPI_Init) with a pattern fixed at
// construction, factorised by SuiteSparse's KLU (sparse LU) or, for a system dominated by large
// dense blocks, by Amesos' LAPACK dense LU (see dense_factorisation_is_faster). The symbolic
// factorisation (ordering) is computed once, at the first factorisation, and reused: only the
// values change between Newton setups.
//
// KLU is called directly on the matrix's own compressed rows (no copy): read as compressed
// columns they are A^T, so a solve is KLU's transposed solve. A refactorisation reuses the last
// pivot order (klu_refactor, no pivot search) and falls back to a factorisation with partial
// pivoting when the pivots have become poor (see factorize()). Through Amesos, each
// factorisation copied the matrix into Amesos' own arrays, searched pivots afresh, and each solve
// read the clock twice for Amesos' timers: 7 % of a tight-tolerance laser robot run.
#pragma once

#include <memory>
#include <set>
#include <vector>

class Epetra_SerialComm;
class Epetra_Map;
class Epetra_CrsGraph;
class Epetra_CrsMatrix;
class Epetra_LinearProblem;
class Epetra_Vector;
class Amesos_BaseSolver;

namespace flextrack::multibody
{
class System;

/// Whether LAPACK's dense LU factorises the Jacobian of @p system (n unknowns) faster than KLU,
/// given the dense blocks its bodies' equations form (m = each body's velocities: its rows are
/// dense in its own coordinates). KLU's left-looking kernel, without BLAS, spends about
/// sum m^3 operations on those blocks at a far lower rate than BLAS-3: the laser robot with its
/// full FE bases (n = 2334, one block of 995) took 4.5 s per KLU factorisation (87 % of its
/// run, 2026-12-02). Dense when n >= 1000 and 20 sum m^3 > n^3 (20: the measured speed ratio,
/// rounded down); every scene of the test suite has n < 1000, or small blocks, and stays on KLU.
bool dense_factorisation_is_faster(const System &system);

class JacobianSolver
{
public:
  /// @p pattern[row]: the columns of row; @p dense: factorise by LAPACK's dense LU, not KLU.
  explicit JacobianSolver(const std::vector<std::set<int>> &pattern, bool dense = false);
  ~JacobianSolver();
  void zero();
  /// A(rows[i], cols[k]) += block[i * cols.size() + k].
  void add(const std::vector<unsigned int> &rows, const std::vector<unsigned int> &cols, const double *block);
  void add(unsigned int row, unsigned int col, double value);
  const Epetra_CrsMatrix &matrix() const { return *A; }
  /// false if the factorisation finds the matrix singular. @p fresh_pivots: KLU searches pivots
  /// afresh instead of reusing the last order (after a Newton failure: the old order may be why).
  bool factorize(bool fresh_pivots = false);
  void solve(const double *b, double *x);
  unsigned long n_factorizations() const { return count; }

private:
  std::unique_ptr<Epetra_SerialComm> comm;
  std::unique_ptr<Epetra_Map> map;
  std::unique_ptr<Epetra_CrsGraph> graph;
  std::unique_ptr<Epetra_CrsMatrix> A;
  // The dense path only (Amesos' LAPACK LU on the problem A x = b):
  std::unique_ptr<Epetra_Vector> x_vec, b_vec;
  std::unique_ptr<Epetra_LinearProblem> problem;
  std::unique_ptr<Amesos_BaseSolver> lu;
  bool symbolic_done = false;
  unsigned long count = 0;
  struct Klu; ///< KLU's settings, ordering and factors (the sparse path; jacobian_solver.cc)
  std::unique_ptr<Klu> klu;
  bool factorize_with_klu(bool fresh_pivots);
  std::vector<int> index_buffer;
};
} // namespace flextrack::multibody
