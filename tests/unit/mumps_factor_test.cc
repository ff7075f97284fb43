// MUMPS's symmetric indefinite LDL^T, called directly (reduction/mumps_factor.h), on K - sigma M
// of a clamped steel block with sigma between its eigenvalues: an indefinite matrix, the case
// for which the distributed reduction and the Cholesky fallback need LDL^T with pivoting.
#include "steel_solid.h"

#include <fem/solid_model.h>
#include <reduction/modal_solver.h>
#include <reduction/mumps_factor.h>

#include <deal.II/lac/vector.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

using namespace flextrack;

TEST(MumpsFactor, solves_an_indefinite_shifted_matrix_and_counts_the_eigenvalues_below_the_shift)
{
  fem::Solid body = test_support::steel_solid(fem::generate_box(dealii::Point<3>(0.1, 0.1, 0.3), {{4, 4, 12}}), "ZMIN");
  const fem::SolidModel model(body);
  const auto &K = model.stiffness_matrix();
  const auto &M = model.mass_matrix();
  // The lowest modes by the default path (CHOLMOD, a negative shift): the reference spectrum.
  reduction::ModalSettings settings;
  settings.n_modes = 8;
  const reduction::Modes modes =
    reduction::lowest_modes(K, M, model.n_free_dofs(), settings, reduction::automatic_shift(K, M), "cholmod");
  const auto &l = modes.eigenvalues;
  // sigma halfway between modes 3 and 4 (0-based 2 and 3), which are apart by more than 5 %.
  unsigned int below = 0;
  for (unsigned int k = 0; k + 1 < l.size() && below == 0; ++k)
    if (k >= 2 && l[k + 1] > 1.05 * l[k]) below = k + 1;
  ASSERT_GT(below, 0u) << "no gap in the spectrum to put the shift in";
  const double sigma = 0.5 * (l[below - 1] + l[below]);
  dealii::TrilinosWrappers::SparseMatrix A;
  A.copy_from(K);
  A.add(-sigma, M);

  // The host's buffers limited to two columns: three right-hand sides go in two solves.
  const unsigned int n = A.m(), k = 3;
  reduction::MumpsFactor factor(A.trilinos_matrix(), 2 * n);
  factor.factorize();
  // Sylvester's law of inertia: as many negative pivots as eigenvalues below sigma (the clamped
  // dofs carry no mass and add none).
  std::cout << "  sigma between modes " << below << " and " << below + 1 << ": " << factor.negative_pivots()
            << " negative pivots\n";
  EXPECT_EQ(factor.negative_pivots(), static_cast<int>(below));

  // Three right-hand sides b = A x0 solved in two blocks, and one alone: the backward error
  // |A x - b| / (|A|_F |x|) at round-off (1e-13: a backward-stable LDL^T with pivoting gives
  // a small multiple of the machine epsilon 2.2e-16), and the block solve equal to the single one.
  std::vector<double> x0(n * k), B(n * k), X(n * k), x_single(n);
  for (unsigned int i = 0; i < n * k; ++i) x0[i] = std::sin(0.37 * i + 0.1) + (i % 7 == 0 ? 1.0 : 0.0);
  for (unsigned int c = 0; c < k; ++c)
    {
      dealii::Vector<double> in(x0.begin() + c * n, x0.begin() + (c + 1) * n), out(n);
      A.vmult(out, in);
      std::copy(out.begin(), out.end(), B.begin() + c * n);
    }
  factor.solve_many(B.data(), X.data(), k);
  factor.solve_many(B.data() + n, x_single.data(), 1);
  const double norm_A = A.frobenius_norm();
  for (unsigned int c = 0; c < k; ++c)
    {
      dealii::Vector<double> x(X.begin() + c * n, X.begin() + (c + 1) * n), r(n);
      A.vmult(r, x);
      for (unsigned int i = 0; i < n; ++i) r[i] -= B[c * n + i];
      const double backward = r.l2_norm() / (norm_A * x.l2_norm());
      std::cout << "  right-hand side " << c << ": backward error " << backward << '\n';
      EXPECT_LT(backward, 1e-13) << "right-hand side " << c;
    }
  double difference = 0, size = 0;
  for (unsigned int i = 0; i < n; ++i)
    {
      difference = std::max(difference, std::abs(x_single[i] - X[n + i]));
      size = std::max(size, std::abs(X[n + i]));
    }
  EXPECT_LE(difference, 1e-12 * size) << "the block solve differs from the single one";
}
