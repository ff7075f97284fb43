// The sparse Jacobian of the DAE and its direct solver: an Epetra_CrsMatrix on an
// Epetra_SerialComm (serial, so `flextrack run` needs no MPI_Init) with a pattern fixed at
// construction, factorised by Amesos KLU. The symbolic factorisation (ordering) is computed once,
// at the first factorisation, and reused: only the values change between Newton setups.
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
class JacobianSolver
{
public:
  /// @p pattern[row]: the columns of row.
  explicit JacobianSolver(const std::vector<std::set<int>> &pattern);
  ~JacobianSolver();
  void zero();
  /// A(rows[i], cols[k]) += block[i * cols.size() + k].
  void add(const std::vector<unsigned int> &rows, const std::vector<unsigned int> &cols, const double *block);
  void add(unsigned int row, unsigned int col, double value);
  const Epetra_CrsMatrix &matrix() const { return *A; }
  /// false if KLU finds the matrix singular.
  bool factorize();
  void solve(const double *b, double *x);
  unsigned long n_factorizations() const { return count; }

private:
  std::unique_ptr<Epetra_SerialComm> comm;
  std::unique_ptr<Epetra_Map> map;
  std::unique_ptr<Epetra_CrsGraph> graph;
  std::unique_ptr<Epetra_CrsMatrix> A;
  std::unique_ptr<Epetra_Vector> x_vec, b_vec;
  std::unique_ptr<Epetra_LinearProblem> problem;
  std::unique_ptr<Amesos_BaseSolver> klu;
  bool symbolic_done = false;
  unsigned long count = 0;
  std::vector<int> index_buffer;
};
} // namespace flextrack::multibody
