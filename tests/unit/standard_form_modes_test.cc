// The eigen solve on the standard form L^{-1} P M P^T L^{-T} y = y / (lambda - sigma), which
// runs whenever the factor of K - sigma M is a supernodal Cholesky factor (one process), against
// the generalised shift-invert form (K - sigma M)^{-1} M on an LDL^T factor by MUMPS, another
// direct solver (reduction/modal_solver.cc).
#include "steel_solid.h"

#include <fem/solid_model.h>
#include <reduction/modal_solver.h>
#include <reduction/sparse_factorization.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

using namespace flextrack;

TEST(StandardFormModes, halves_of_the_factor_and_the_modes_agree_with_the_generalised_form)
{
  // A clamped block of 4 x 4 x 12 hex20 cells (4 131 dofs): large enough for CHOLMOD to choose
  // a supernodal factor.
  fem::Solid body = test_support::steel_solid(fem::generate_box(dealii::Point<3>(0.1, 0.1, 0.3), {{4, 4, 12}}), "ZMIN");
  const fem::SolidModel model(body);
  const auto &K = model.stiffness_matrix();
  const auto &M = model.mass_matrix();
  const double sigma = reduction::automatic_shift(K, M);
  const reduction::SparseFactorization cholesky(K, M, sigma, "cholmod");
  ASSERT_TRUE(cholesky.has_halves()) << "the test needs a supernodal factor";

  // Halves: P^T L^{-T} (L^{-1} P b) = A^{-1} b. Bound 1e-12 of max |x| (round-off of two
  // triangular solves in either order; cond(A) of a stiffness matrix enters both alike).
  const std::size_t n = K.m();
  std::vector<double> b(n), y(n), x_halves(n), x(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = std::sin(0.7 * i + 0.3);
  cholesky.solve_lower(b.data(), y.data());
  cholesky.solve_upper(y.data(), x_halves.data());
  cholesky.solve(b.data(), x.data());
  double largest = 0, difference = 0;
  for (std::size_t i = 0; i < n; ++i)
    {
      largest = std::max(largest, std::abs(x[i]));
      difference = std::max(difference, std::abs(x[i] - x_halves[i]));
    }
  EXPECT_LT(difference, 1e-12 * largest);

  // 8 modes both ways: eigenvalues to 1e-10 relative (ARPACK's tolerance 1e-12 on each side);
  // each shape of a single eigenvalue (its neighbours computed and apart) the same as the other
  // up to sign: |phi_standard^T M phi_generalised| = 1 to 1e-8 (both are mass-normalised).
  reduction::ModalSettings settings;
  settings.n_modes = 8;
  const reduction::Modes standard = reduction::lowest_modes(K, M, model.n_free_dofs(), settings, sigma, cholesky);
  const reduction::Modes generalised = reduction::lowest_modes(K, M, model.n_free_dofs(), settings, sigma, "mumps");
  ASSERT_EQ(standard.eigenvalues.size(), generalised.eigenvalues.size());
  unsigned int n_single = 0;
  for (unsigned int k = 0; k < standard.eigenvalues.size(); ++k)
    {
      const double l1 = standard.eigenvalues[k], l2 = generalised.eigenvalues[k];
      EXPECT_NEAR(l1, l2, 1e-10 * l2) << "mode " << k;
      // The bending modes of the square section come in pairs, whose shapes are any basis.
      const auto &l = standard.eigenvalues;
      const bool single = k > 0 && k + 1 < l.size() && l[k] - l[k - 1] > 1e-6 * l[k] && l[k + 1] - l[k] > 1e-6 * l[k];
      if (single)
        {
          ++n_single;
          dealii::Vector<double> M_phi(n);
          M.vmult(M_phi, generalised.shapes[k]);
          EXPECT_NEAR(std::abs(standard.shapes[k] * M_phi), 1.0, 1e-8) << "mode " << k;
        }
      std::cout << "  mode " << k << ": " << std::sqrt(l1) / (2 * M_PI) << " Hz, relative difference "
                << std::abs(l1 - l2) / l2 << (single ? ", shapes compared" : "") << '\n';
    }
  EXPECT_GE(n_single, 2u);
}
