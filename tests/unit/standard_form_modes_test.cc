// The eigen solve on the standard form L^{-1} P M P^T L^{-T} y = y / (lambda - sigma), which
// runs whenever the factor of K - sigma M is a supernodal Cholesky factor (one process), against
// the generalised shift-invert form (K - sigma M)^{-1} M on an LDL^T factor by MUMPS, another
// direct solver (reduction/modal_solver.cc).
#include "steel_solid.h"

#include <fem/solid_model.h>
#include <reduction/modal_solver.h>
#include <reduction/sparse_factorization.h>
#include <base/solver_error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <iostream>
#include <vector>

using namespace flextrack;

namespace
{
/// The lowest @p n_modes of @p body both ways (the standard form on CHOLMOD's halves, the
/// generalised form on a MUMPS factor): eigenvalues to 1e-10 of the largest (ARPACK's tolerance
/// 1e-12 on each side; the rigid-body modes of a free body are zero to round-off); each shape of
/// a single eigenvalue (its neighbours computed and apart) the same as the other up to sign:
/// |phi_standard^T M phi_generalised| = 1 to 1e-8 (both are mass-normalised). Returns the number
/// of shapes compared.
unsigned int compare_forms(const fem::SolidModel &model, const unsigned int n_modes)
{
  const auto &K = model.stiffness_matrix();
  const auto &M = model.mass_matrix();
  const double sigma = reduction::automatic_shift(K, M);
  const reduction::SparseFactorization cholesky(K, M, sigma, "cholmod");
  EXPECT_TRUE(cholesky.has_halves()) << "the test needs a supernodal factor";
  reduction::ModalSettings settings;
  settings.n_modes = n_modes;
  const reduction::Modes standard = reduction::lowest_modes(K, M, model.n_free_dofs(), settings, sigma, cholesky);
  const reduction::Modes generalised = reduction::lowest_modes(K, M, model.n_free_dofs(), settings, sigma, "mumps");
  EXPECT_EQ(standard.eigenvalues.size(), n_modes);
  EXPECT_EQ(generalised.eigenvalues.size(), n_modes);
  const auto &l = standard.eigenvalues;
  unsigned int n_single = 0;
  for (unsigned int k = 0; k < n_modes; ++k)
    {
      EXPECT_NEAR(l[k], generalised.eigenvalues[k], 1e-10 * l.back()) << "mode " << k;
      // Pairs (the bending modes of a square section) and the rigid-body modes: any basis.
      const bool single = k > 0 && k + 1 < l.size() && l[k] > 1e-8 * l.back() && l[k] - l[k - 1] > 1e-6 * l[k] &&
                          l[k + 1] - l[k] > 1e-6 * l[k];
      if (single)
        {
          ++n_single;
          dealii::Vector<double> M_phi(K.m());
          M.vmult(M_phi, generalised.shapes[k]);
          EXPECT_NEAR(std::abs(standard.shapes[k] * M_phi), 1.0, 1e-8) << "mode " << k;
        }
      std::cout << "  mode " << k << ": " << std::sqrt(std::max(l[k], 0.0)) / (2 * M_PI) << " Hz, difference "
                << std::abs(l[k] - generalised.eigenvalues[k]) / l.back() << " of the largest"
                << (single ? ", shapes compared" : "") << '\n';
    }
  return n_single;
}
} // namespace

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

  EXPECT_GE(compare_forms(model, 8), 2u);

  // A free block (no supports, a negative shift): six rigid-body modes, then elastic ones.
  fem::Solid free_body = body;
  free_body.supports.clear();
  const fem::SolidModel free_model(free_body);
  EXPECT_GE(compare_forms(free_model, 12), 2u);
}

TEST(SparseFactorization, refuses_a_factor_that_does_not_fit)
{
  // The clamped block above. The estimate made before factorising lies between what any
  // Cholesky or LDL^T factor holds at least (the entries of A's lower triangle, 8 bytes each;
  // fill-in only adds) and the dense triangle (n (n + 1) / 2 entries): bounds of the method, not
  // of this code. With FLEXTRACK_MEMORY_LIMIT below what the process holds already, both
  // methods refuse before they factorise, with a SolverError that says so.
  fem::Solid body = test_support::steel_solid(fem::generate_box(dealii::Point<3>(0.1, 0.1, 0.3), {{4, 4, 12}}), "ZMIN");
  const fem::SolidModel model(body);
  const auto &K = model.stiffness_matrix();
  const auto &M = model.mass_matrix();
  const double n = K.m();
  const double lower_triangle = (static_cast<double>(K.n_nonzero_elements()) + n) / 2;
  for (const std::string method : {"cholmod", "mumps"})
    {
      const reduction::SparseFactorization factor(K, M, -1.0, method);
      const double bytes = factor.memory_estimate_bytes();
      std::cout << "  " << method << ": estimate " << bytes / 1048576 << " MiB for " << n << " dofs\n";
      EXPECT_GE(bytes, 8 * lower_triangle) << method;
      EXPECT_LE(bytes, 8 * n * (n + 1) / 2 + 16 * K.n_nonzero_elements()) << method;
    }
  struct Limit // set for this scope only, whatever ends it
  {
    Limit() { setenv("FLEXTRACK_MEMORY_LIMIT", "1e-6", 1); }
    ~Limit() { unsetenv("FLEXTRACK_MEMORY_LIMIT"); }
  } limit;
  for (const std::string method : {"cholmod", "mumps"})
    try
      {
        const reduction::SparseFactorization factor(K, M, -1.0, method);
        ADD_FAILURE() << method << ": factorised beyond the memory limit";
      }
    catch (const SolverError &e)
      {
        const std::string text = e.what();
        EXPECT_NE(text.find("factorisation"), std::string::npos) << text;
        EXPECT_NE(text.find("of the " + std::to_string(K.m()) + "-dof matrix needs about"), std::string::npos) << text;
        EXPECT_NE(text.find("it was not started"), std::string::npos) << text;
      }
}
