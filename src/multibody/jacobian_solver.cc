// Epetra matrix and Amesos KLU factorisation of the DAE Jacobian (jacobian_solver.h).
#include <multibody/jacobian_solver.h>
#include <multibody/system.h>

#include <Amesos.h>
#include <Amesos_BaseSolver.h>
#include <Epetra_CrsGraph.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_LinearProblem.h>
#include <Epetra_Map.h>
#include <Epetra_SerialComm.h>
#include <Epetra_Vector.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace flextrack::multibody
{
bool dense_factorisation_is_faster(const System &system)
{
  double blocks = 0;
  for (unsigned int b = 0; b < system.n_bodies(); ++b) blocks += std::pow(double(system.body(b).n_v()), 3);
  const unsigned int n = system.size();
  return n >= 1000 && 20 * blocks > std::pow(double(n), 3);
}

JacobianSolver::JacobianSolver(const std::vector<std::set<int>> &pattern, const bool dense)
{
  const int n = pattern.size();
  comm = std::make_unique<Epetra_SerialComm>();
  map = std::make_unique<Epetra_Map>(n, 0, *comm);
  std::vector<int> per_row(n);
  for (int i = 0; i < n; ++i) per_row[i] = pattern[i].size();
  graph = std::make_unique<Epetra_CrsGraph>(Copy, *map, per_row.data(), true);
  for (int i = 0; i < n; ++i)
    {
      std::vector<int> cols(pattern[i].begin(), pattern[i].end());
      graph->InsertGlobalIndices(i, cols.size(), cols.data());
    }
  graph->FillComplete();
  graph->OptimizeStorage();
  A = std::make_unique<Epetra_CrsMatrix>(Copy, *graph);
  x_vec = std::make_unique<Epetra_Vector>(*map);
  b_vec = std::make_unique<Epetra_Vector>(*map);
  problem = std::make_unique<Epetra_LinearProblem>(A.get(), x_vec.get(), b_vec.get());
  Amesos factory;
  const char *kind = dense ? "Amesos_Lapack" : "Amesos_Klu";
  lu.reset(factory.Create(kind, *problem));
  if (!lu) throw std::runtime_error(std::string(kind) + " is not available in this Trilinos");
}

JacobianSolver::~JacobianSolver() = default;

void JacobianSolver::zero() { A->PutScalar(0.0); }

void JacobianSolver::add(const std::vector<unsigned int> &rows, const std::vector<unsigned int> &cols, const double *block)
{
  index_buffer.assign(cols.begin(), cols.end());
  for (unsigned int i = 0; i < rows.size(); ++i)
    {
      const int err = A->SumIntoGlobalValues(static_cast<int>(rows[i]), cols.size(), block + i * cols.size(), index_buffer.data());
      if (err != 0) throw std::logic_error("JacobianSolver: entry outside the pattern (row " + std::to_string(rows[i]) + ")");
    }
}

void JacobianSolver::add(const unsigned int row, const unsigned int col, const double value)
{
  int c = col;
  const int err = A->SumIntoGlobalValues(static_cast<int>(row), 1, &value, &c);
  if (err != 0) throw std::logic_error("JacobianSolver: entry outside the pattern");
}

bool JacobianSolver::factorize()
{
  if (!symbolic_done)
    {
      if (lu->SymbolicFactorization() != 0) return false;
      symbolic_done = true;
    }
  ++count;
  return lu->NumericFactorization() == 0;
}

void JacobianSolver::solve(const double *b, double *x)
{
  const int n = map->NumMyElements();
  std::memcpy(b_vec->Values(), b, n * sizeof(double));
  lu->Solve();
  std::memcpy(x, x_vec->Values(), n * sizeof(double));
}
} // namespace flextrack::multibody
