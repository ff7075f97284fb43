#include <reduction/linear_solver.h>
#include <reduction/modal_solver.h>

#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_solver.h>

namespace flextrack::reduction
{
using namespace dealii;

Vector<double> solve_direct(const TrilinosWrappers::SparseMatrix &A, const Vector<double> &b)
{
  SolverControl control(1, 0);
  TrilinosWrappers::SolverDirect direct(control, TrilinosWrappers::SolverDirect::AdditionalData(false, "Amesos_Klu"));
  Vector<double> x(b.size());
  try
    {
      direct.solve(A, x, b);
    }
  catch (const std::exception &)
    {
      throw SolverError("the stiffness matrix is singular: the structure is not supported against every rigid "
                        "motion; add supports");
    }
  return x;
}

Vector<double> solve_with_prescribed_values(const TrilinosWrappers::SparseMatrix &K, const IndexSet &prescribed,
                                            const Vector<double> &values, const Vector<double> &f)
{
  // Rows of prescribed dofs become u_i = value_i; the other rows keep their coupling to them.
  TrilinosWrappers::SparseMatrix A;
  A.copy_from(K);
  Vector<double> rhs(K.m());
  if (f.size() == K.m()) rhs = f;
  for (const auto i : prescribed)
    {
      A.clear_row(i, 1.0);
      rhs[i] = values[i];
    }
  return solve_direct(A, rhs);
}
} // namespace flextrack::reduction
