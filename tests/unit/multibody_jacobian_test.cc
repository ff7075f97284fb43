// The assembled DAE Jacobian dF/dy + alpha dF/dy' against central differences of the whole
// residual, at a state that satisfies nothing (random multipliers, velocities, accelerations),
// so that every block - including the multiplier terms' derivatives - is exercised. Also: the
// joint Jacobian B against differences of Phi along T v, and a small program-level check that the
// engine does not need MPI.
#include "multibody_test_helpers.h"

#include <multibody/force.h>
#include <multibody/jacobian_solver.h>

#include <Epetra_CrsMatrix.h>

#include <gtest/gtest.h>

#include <iostream>
#include <random>

using namespace flextrack;
using namespace flextrack::multibody;
using namespace flextrack::multibody::test;
using dealii::FullMatrix;
using dealii::Vector;

namespace
{
/// Slider-crank with gravity, a spring-damper from the slider to the ground, an applied load on
/// the rod and a rotational spring-damper at the crank pin.
void build(System &s)
{
  const double r = 0.1, l = 0.3;
  add_rigid(s, "crank", 0.5, diagonal(1e-4, 5e-4, 5e-4), Vector3({r / 2, 0, 0}), {{1, 0, 0, 0}}, Vector3(), Vector3(),
            Vector3({0.01, 0.02, 0}));
  add_rigid(s, "rod", 1.0, diagonal(1e-4, 8e-3, 8e-3), Vector3({r + l / 2, 0, 0}));
  add_rigid(s, "slider", 2.0, diagonal(1e-3, 2e-3, 3e-3), Vector3({r + l, 0, 0}));
  add_joint(s, "revolute", "drive", "crank", "ground", Vector3(), Vector3({0, 0, 1}), "2*pi*t + 0.3*sin(5*t)");
  add_joint(s, "revolute", "crank_pin", "rod", "crank", Vector3({r, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "spherical", "wrist_pin", "slider", "rod", Vector3({r + l, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "prismatic", "guide", "slider", "ground", Vector3({r + l, 0, 0}), Vector3({1, 0, 0}), "", Vector3({0, 1, 0}));
  auto marker = [&](const std::string &body, const Vector3 &x, const std::string &name) {
    const Body &b = *s.find_body(body);
    std::vector<double> q(b.n_q()), v(b.n_v());
    b.initial_coordinates(q.data(), v.data());
    return FixedMarker::at_global_pose(b, name, x, diagonal(1, 1, 1), q.data());
  };
  s.add_force(std::make_unique<SpringDamper>("spring", marker("slider", Vector3({r + l, 0.05, 0}), "s1"),
                                             marker("ground", Vector3({1, 0.2, 0}), "s2"), 100, 3, 0.5));
  s.add_force(std::make_unique<AppliedLoad>(
    "push", marker("rod", Vector3({r + 0.1, 0, 0.01}), "p1"),
    std::array<geometry::Expression, 3>{{geometry::Expression("sin(t)", "t"), geometry::Expression("2", "t"), geometry::Expression("t", "t")}},
    std::array<geometry::Expression, 3>{{geometry::Expression("0.1", "t"), geometry::Expression("0", "t"), geometry::Expression("cos(t)", "t")}},
    true));
  s.add_force(std::make_unique<RotationalSpringDamper>("torsion", marker("rod", Vector3({r, 0, 0}), "r1"),
                                                       marker("crank", Vector3({r, 0, 0}), "r2"), 5, 0.2, 0.1));
}

} // namespace

TEST(MultibodyJacobian, assembled_jacobian_matches_central_differences_of_residual)
{
  System s(Vector3({0, -9.81, 0}));
  build(s);
  s.finalize();
  Vector<double> y, yp;
  consistent_initial_conditions(s, 0, y, yp); // drops the redundant rows; a valid layout
  // Move away from the solution: random perturbation of every unknown and derivative.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (unsigned int i = 0; i < y.size(); ++i) y[i] += 0.05 * u(rng), yp[i] += 0.5 * u(rng);
  for (unsigned int i = s.n_q() + s.n_v(); i < y.size(); ++i) y[i] = 3 * u(rng); // multipliers
  const double t = 0.37, alpha = 123.4;
  s.assemble_jacobian(t, alpha, y, yp);
  const Epetra_CrsMatrix &J = s.jacobian();

  // Reference: (F(y + h e_c, yp + alpha h e_c) - F(y - h e_c, yp - alpha h e_c)) / 2h, h = 1e-6
  // (central differences of the full residual: error ~1e-9 relative to the largest entry).
  double worst = 0, largest = 0;
  unsigned int worst_row = 0, worst_col = 0;
  Vector<double> Fp, Fm;
  for (unsigned int c = 0; c < y.size(); ++c)
    {
      const double h = 1e-6 * (1 + std::abs(y[c]));
      Vector<double> y1(y), y2(y), yp1(yp), yp2(yp);
      y1[c] += h, y2[c] -= h, yp1[c] += alpha * h, yp2[c] -= alpha * h;
      s.residual(t, y1, yp1, Fp);
      s.residual(t, y2, yp2, Fm);
      for (unsigned int r = 0; r < y.size(); ++r)
        {
          const double fd = (Fp[r] - Fm[r]) / (2 * h), a = matrix_entry(J, r, c);
          largest = std::max(largest, std::abs(fd));
          if (std::abs(fd - a) > worst) worst = std::abs(fd - a), worst_row = r, worst_col = c;
        }
    }
  std::cout << "  Jacobian " << y.size() << " x " << y.size() << ", " << J.NumGlobalNonzeros()
            << " stored entries: max |J - J_fd| = " << worst << " (row " << s.component_name(worst_row) << ", column "
            << s.component_name(worst_col) << "), max |J_fd| = " << largest << "\n";
  // Tolerance 1e-7 relative to the largest entry: both sides are central differences with
  // h ~ 1e-6 (truncation ~h^2 * third derivatives, rounding ~1e-16 / h).
  EXPECT_LT(worst, 1e-7 * largest);
  EXPECT_TRUE(s.factorize());
}

TEST(MultibodyJacobian, joint_jacobian_is_the_derivative_of_phi_along_the_motion)
{
  // B v must equal d/dt Phi(q + s T v) at s = 0 (central difference, step 1e-6: 1e-8 absolute).
  System s;
  build(s);
  s.finalize();
  Vector<double> y, yp;
  s.initial_guess(y);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (unsigned int i = 0; i < s.n_q() + s.n_v(); ++i) y[i] += 0.1 * u(rng);
  Vector<double> phi, phi_t, phi_p, phi_m, v(s.n_v()), Bv;
  FullMatrix<double> B, Bx;
  s.constraints(1.0, y, true, phi, B, phi_t);
  for (unsigned int i = 0; i < s.n_v(); ++i) v[i] = y[s.n_q() + i];
  Bv.reinit(B.m());
  B.vmult(Bv, v);
  const double eps = 1e-6;
  Vector<double> yp1(y), ym1(y), dv(v);
  dv *= eps;
  s.move_positions(yp1, dv); // q + eps T v (renormalised p: Phi is invariant to |p|)
  dv *= -1;
  s.move_positions(ym1, dv);
  s.constraints(1.0, yp1, true, phi_p, Bx, phi_t);
  s.constraints(1.0, ym1, true, phi_m, Bx, phi_t);
  double worst = 0;
  for (unsigned int r = 0; r < B.m(); ++r) worst = std::max(worst, std::abs((phi_p[r] - phi_m[r]) / (2 * eps) - Bv[r]));
  std::cout << "  max |B v - dPhi/dt| = " << worst << "\n";
  EXPECT_LT(worst, 1e-8);
}

TEST(MultibodyJacobian, solver_finds_entries_by_table_and_by_bisection)
{
  // JacobianSolver::add finds an entry through a table of all n^2 places up to 1500 unknowns and
  // by bisection of the row above: both, with KLU and the dense LU, on an arrow-shaped matrix
  // A = tridiag(-1, 4, -1) + 0.5 in column 0, with b = A x for a chosen x (a manufactured
  // solution): the solve must return x to 1e-12, copy_to_dense must hold exactly the entries
  // added, and an entry outside the pattern or the matrix must be refused.
  for (const int n : {50, 1600})
    for (const bool dense : {false, true})
      {
        if (dense && n > 100) continue; // the dense LU of 1600 adds nothing here
        std::vector<std::vector<int>> pattern(n);
        for (int i = 0; i < n; ++i)
          {
            if (i > 1) pattern[i].push_back(0);
            for (int j = std::max(0, i - 1); j <= std::min(n - 1, i + 1); ++j) pattern[i].push_back(j);
          }
        JacobianSolver solver(pattern, dense);
        solver.zero();
        std::vector<double> x(n), b(n, 0.0);
        for (int i = 0; i < n; ++i) x[i] = std::sin(0.1 * i + 0.3);
        for (int i = 0; i < n; ++i)
          {
            solver.add(i, i, 4.0);
            b[i] += 4.0 * x[i];
            if (i > 0) solver.add(i, i - 1, -1.0), b[i] -= x[i - 1];
            if (i + 1 < n) solver.add(i, i + 1, -1.0), b[i] -= x[i + 1];
            if (i > 1) solver.add(std::vector<unsigned int>{static_cast<unsigned int>(i)}, {0u}, std::vector<double>{0.5}.data()), b[i] += 0.5 * x[0];
          }
        std::vector<double> A;
        copy_to_dense(solver.matrix(), A);
        double sum = 0;
        for (const double a : A) sum += a;
        EXPECT_DOUBLE_EQ(sum, 4.0 * n - 2.0 * (n - 1) + 0.5 * (n - 2)) << "n = " << n;
        EXPECT_EQ(A[std::size_t(0) * n + (n - 1)], 0.5); // (n - 1, 0), column major
        ASSERT_TRUE(solver.factorize());
        std::vector<double> solution(n);
        solver.solve(b.data(), solution.data());
        double worst = 0;
        for (int i = 0; i < n; ++i) worst = std::max(worst, std::abs(solution[i] - x[i]));
        EXPECT_LT(worst, 1e-12) << "n = " << n << (dense ? ", dense LU" : ", KLU");
        EXPECT_THROW(solver.add(10, 40, 1.0), std::logic_error);     // inside the matrix, outside the pattern
        EXPECT_THROW(solver.add(10, n, 1.0), std::logic_error);      // outside the matrix
        EXPECT_THROW(solver.add(n + 3, 0, 1.0), std::logic_error);
      }
}

TEST(MultibodyJacobian, newton_matrix_leaves_out_only_the_stabilisation_curvature_and_condenses_the_positions)
{
  // System::use_newton_matrix: the Newton matrix of a time step is the exact Jacobian without the
  // joints' d(Phi_q^T mu)/dq. Reference: the exact Jacobian (checked against central differences
  // above). At a random state with mu = 0 both must agree to round-off (1e-13 of the largest
  // entry); with random mu they differ only in the position rows' position columns. Its LU then
  // condenses the positions out (every block is a body's R and p: 7 unknowns), and the solve
  // returns a manufactured x to 1e-10 (relative to |x| = 1; the matrix' condition number is about
  // 1e4 at cj = 123.4).
  System s(Vector3({0, -9.81, 0}));
  build(s);
  s.finalize();
  Vector<double> y, yp;
  consistent_initial_conditions(s, 0, y, yp);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (unsigned int i = 0; i < y.size(); ++i) y[i] += 0.05 * u(rng), yp[i] += 0.5 * u(rng);
  const unsigned int n = y.size(), nq = s.n_q(), mu0 = s.n_q() + s.n_v() + s.n_lambda();
  for (unsigned int i = s.n_q() + s.n_v(); i < n; ++i) y[i] = 3 * u(rng);
  const double t = 0.37, alpha = 123.4;
  const auto dense = [&](const bool newton, const Vector<double> &state) {
    s.use_newton_matrix(newton);
    s.assemble_jacobian(t, alpha, state, yp);
    std::vector<double> A;
    copy_to_dense(s.jacobian(), A);
    return A;
  };
  const std::vector<double> exact = dense(false, y), newton = dense(true, y);
  double largest = 0, outside = 0, inside = 0;
  for (unsigned int c = 0; c < n; ++c)
    for (unsigned int r = 0; r < n; ++r)
      {
        const std::size_t k = std::size_t(c) * n + r;
        largest = std::max(largest, std::abs(exact[k]));
        (r < nq && c < nq ? inside : outside) = std::max(r < nq && c < nq ? inside : outside, std::abs(exact[k] - newton[k]));
      }
  EXPECT_EQ(outside, 0.0) << "the Newton matrix differs outside the position rows' position columns";
  EXPECT_GT(inside, 1e-6 * largest) << "random mu: the curvature term should show";
  Vector<double> y0(y);
  for (unsigned int i = mu0; i < mu0 + s.n_lambda(); ++i) y0[i] = 0; // the joints' mu
  const std::vector<double> exact0 = dense(false, y0), newton0 = dense(true, y0);
  double worst = 0;
  for (std::size_t k = 0; k < exact0.size(); ++k) worst = std::max(worst, std::abs(exact0[k] - newton0[k]));
  EXPECT_LT(worst, 1e-13 * largest);

  // The condensed LU of the Newton matrix.
  dense(true, y);
  ASSERT_TRUE(s.factorize());
  EXPECT_EQ(s.n_condensed_factorizations(), 1u);
  EXPECT_EQ(s.condensed_size(), n - nq);
  std::vector<double> x(n), b(n, 0.0), solution(n);
  for (unsigned int i = 0; i < n; ++i) x[i] = std::cos(0.3 * i + 0.1);
  for (unsigned int c = 0; c < n; ++c)
    for (unsigned int r = 0; r < n; ++r) b[r] += newton[std::size_t(c) * n + r] * x[c];
  s.solve(b.data(), solution.data());
  double error = 0;
  for (unsigned int i = 0; i < n; ++i) error = std::max(error, std::abs(solution[i] - x[i]));
  EXPECT_LT(error, 1e-10);
}
