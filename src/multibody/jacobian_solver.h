// The sparse Jacobian of the DAE and its direct solver: an Epetra_CrsMatrix on an
// Epetra_SerialComm (serial, so `flextrack run` needs no MPI_Init) with a pattern fixed at
// construction, factorised by SuiteSparse's KLU (sparse LU) or, for a Jacobian that is nearly
// dense or dominated by large dense blocks, by LAPACK's dense LU (dgetrf; see
// dense_factorisation_is_faster). KLU's symbolic factorisation (ordering) is computed once, at
// the first factorisation, and reused: only the values change between Newton setups.
//
// KLU is called directly on the matrix's own compressed rows (no copy): read as compressed
// columns they are A^T, so a solve is KLU's transposed solve. A refactorisation reuses the last
// pivot order (klu_refactor, no pivot search) and falls back to a factorisation with partial
// pivoting when the pivots have become poor (see factorize()). Through Amesos, each
// factorisation copied the matrix into Amesos' own arrays, searched pivots afresh, and each solve
// read the clock twice for Amesos' timers: 7 % of a tight-tolerance laser robot run.
#pragma once

#include <multibody/condensed_lu.h>

#include <memory>
#include <vector>

class Epetra_SerialComm;
class Epetra_Map;
class Epetra_CrsGraph;
class Epetra_CrsMatrix;

namespace flextrack::multibody
{
class System;

/// Whether LAPACK's dense LU factorises the Jacobian of @p system (n unknowns, its @p pattern from
/// System::jacobian_pattern) faster than KLU.
/// KLU's left-looking kernel, without BLAS, works at a far lower rate than LAPACK's blocked LU,
/// so dense wins when KLU's factors are nearly full anyway:
///  - the pattern holds at least 30 % of the n^2 entries (n <= 5000). Every element's pattern is
///    its rows x all its columns, and a flexible body's rows are dense in its own coordinates, so
///    the scenes of a few flexible bodies are 60-99 % dense (the laser robot: n = 170, 59 %, with
///    KLU's L + U holding 64 % of n^2; its integration took 14 % less time with the dense LU,
///    2026-12-02). A chain of 16 flexible links (n = 704, 15 %) stays on KLU;
///  - or large dense blocks dominate (m = each body's velocities): n >= 1000 and 20 sum m^3 > n^3.
///    The laser robot with its full FE bases (n = 2334, one block of 995) took 4.5 s per KLU
///    factorisation (87 % of its run, 2026-12-02); 20 is the measured speed ratio, rounded down.
bool dense_factorisation_is_faster(const System &system, const std::vector<std::vector<int>> &pattern);
/// The share of the n^2 entries of an n x n matrix that @p pattern (each row's columns) holds.
double pattern_fill(const std::vector<std::vector<int>> &pattern);
/// @p A (square, serial, storage optimised: JacobianSolver's is) as a dense column-major n x n
/// array, as LAPACK takes it.
void copy_to_dense(const Epetra_CrsMatrix &A, std::vector<double> &column_major);

class JacobianSolver
{
public:
  /// @p pattern[row]: the columns of row (sorted, no repeats); @p dense: factorise by LAPACK's
  /// dense LU, not KLU (the sparse path is the one with KLU's state). @p n_condensed: the dense
  /// path eliminates the first n_condensed unknowns (the positions) through their small diagonal
  /// blocks before the LU, where those blocks are uncoupled (condensed_lu.h); 0: never.
  explicit JacobianSolver(const std::vector<std::vector<int>> &pattern, bool dense = false, unsigned int n_condensed = 0);
  ~JacobianSolver();
  void zero();
  /// A(rows[i], cols[k]) += block[i * cols.size() + k].
  void add(const std::vector<unsigned int> &rows, const std::vector<unsigned int> &cols, const double *block);
  void add(unsigned int row, unsigned int col, double value);
  const Epetra_CrsMatrix &matrix() const { return *A; }
  /// false if the factorisation finds the matrix singular. @p fresh_pivots: KLU searches pivots
  /// afresh instead of reusing the last order (after a Newton failure: the old order may be why);
  /// the dense LU always does.
  bool factorize(bool fresh_pivots = false);
  void solve(const double *b, double *x);
  unsigned long n_factorizations() const { return count; }
  /// How many of them condensed the positions out (CondensedLU), and its complement's size.
  unsigned long n_condensed_factorizations() const { return condensed_count; }
  unsigned int condensed_size() const { return dense_lu.complement_size(); }

private:
  std::unique_ptr<Epetra_SerialComm> comm;
  std::unique_ptr<Epetra_Map> map;
  std::unique_ptr<Epetra_CrsGraph> graph;
  std::unique_ptr<Epetra_CrsMatrix> A;
  unsigned long count = 0, condensed_count = 0;
  // The dense path only: the LU factors of A (column major, n x n), with the first n_condensed
  // unknowns condensed out where NewtonLU can.
  bool dense_factored = false;
  unsigned int n_condensed = 0;
  NewtonLU<double> dense_lu;
  std::vector<double> dense_factors;
  bool factorize_dense();
  /// The matrix's compressed rows in place: row starts, column indices, values.
  void compressed_rows(int *&row_start, int *&columns, double *&values) const;
  struct Klu; ///< KLU's settings, ordering and factors (the sparse path; jacobian_solver.cc)
  std::unique_ptr<Klu> klu;
  bool factorize_with_klu(bool fresh_pivots);
  /// Up to 1500 unknowns: the place in the value array of (row, col) at row n + col, -1 outside
  /// the pattern.
  std::vector<int> slot_of;
  /// Above 1500 unknowns: for each stored entry, in the order of the compressed rows and sorted
  /// by column within each row, its global column and its place in the value array (bisected).
  std::vector<int> entry_columns, entry_slots;
  int *row_start = nullptr; ///< the matrix' own compressed rows (its storage is optimised: fixed)
  double *values = nullptr;
  unsigned int n_rows = 0;
  double &entry(unsigned int row, unsigned int col);
};
} // namespace flextrack::multibody
