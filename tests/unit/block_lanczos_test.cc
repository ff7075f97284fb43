// Block Lanczos (reduction/block_lanczos.h) on operators whose eigenpairs are known in closed
// form. The solve of a body against ARPACK and MUMPS is in standard_form_modes_test.cc.
#include <reduction/block_lanczos.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

using namespace flextrack;

namespace
{
/// out = T^{-1} in for k columns, T = tridiag(-1, 2, -1) of size n (the Thomas algorithm).
void inverse_laplacian(const double *in, double *out, const unsigned int k, const std::size_t n)
{
  std::vector<double> c(n), d(n);
  for (unsigned int col = 0; col < k; ++col)
    {
      const double *b = in + col * n;
      double *x = out + col * n;
      c[0] = -0.5;
      d[0] = b[0] / 2;
      for (std::size_t i = 1; i < n; ++i)
        {
          const double m = 2 + c[i - 1];
          c[i] = -1 / m;
          d[i] = (b[i] + d[i - 1]) / m;
        }
      x[n - 1] = d[n - 1];
      for (std::size_t i = n - 1; i-- > 0;) x[i] = d[i] - c[i] * x[i + 1];
    }
}
} // namespace

TEST(BlockLanczos, largest_eigenpairs_of_the_inverse_discrete_laplacian)
{
  // T = tridiag(-1, 2, -1), n = 3000: eigenvalues mu_j = 2 - 2 cos(j pi / (n + 1)), vectors
  // sin(i j pi / (n + 1)) (the discrete Laplacian's closed form). T^{-1}'s largest eigenvalues
  // are 1 / mu_1 > 1 / mu_2 > ..., spread like a body's shift-inverted spectrum (1 / j^2).
  // Bounds: eigenvalues to 1e-10 relative and vectors to an angle of 1e-6 (1 - |cos| <= 5e-13),
  // for a residual tolerance of 1e-12 relative: an eigenvalue's error is of the order of the
  // residual squared over the gap, a vector's angle of the residual over the relative gap (here
  // at least 0.2). The operator is scaled by 1e12 for one run: the method must not depend on the
  // operator's size (its tests of vanishing columns are relative).
  const std::size_t n = 3000;
  const unsigned int wanted = 10;
  for (const double scale : {1.0, 1e12})
  for (const unsigned int block : {1u, 3u, 4u, 8u})
    {
      const auto pairs = reduction::block_lanczos(
        [&](const double *in, double *out, unsigned int k) {
          inverse_laplacian(in, out, k, n);
          for (std::size_t i = 0; i < n * k; ++i) out[i] *= scale;
        },
        n, wanted, block, 6 * wanted + 40, 1e-12);
      ASSERT_TRUE(pairs.has_value()) << "block " << block;
      ASSERT_EQ(pairs->values.size(), wanted);
      for (unsigned int j = 1; j <= wanted; ++j)
        {
          const double mu = 2 - 2 * std::cos(j * M_PI / (n + 1));
          EXPECT_NEAR(pairs->values[j - 1] * mu / scale, 1.0, 1e-10) << "block " << block << ", eigenvalue " << j;
          std::vector<double> exact(n);
          for (std::size_t i = 0; i < n; ++i) exact[i] = std::sin((i + 1) * j * M_PI / (n + 1));
          const double *v = pairs->vectors.data() + (j - 1) * n;
          const double cosine = std::inner_product(v, v + n, exact.begin(), 0.0) /
                                std::sqrt(std::inner_product(exact.begin(), exact.end(), exact.begin(), 0.0) *
                                          std::inner_product(v, v + n, v, 0.0));
          EXPECT_LE(1 - std::abs(cosine), 5e-13) << "block " << block << ", vector " << j;
        }
      std::cout << "  block " << block << ": " << pairs->block_steps << " steps, basis " << pairs->basis_size << '\n';
    }
}

TEST(BlockLanczos, repeated_eigenvalues_and_an_invariant_start)
{
  // A diagonal operator with eigenvalue 1 six times (like a free body's six rigid-body modes in
  // the shift-invert operator), then 0.5, 0.4, 1 / i for the rest: a block of 8 (the solver's)
  // finds the whole eigenspace of 1, the eigenvalues to 1e-12.
  const std::size_t n = 500;
  const unsigned int multiple = 6;
  std::vector<double> d(n);
  for (std::size_t i = 0; i < n; ++i) d[i] = i < multiple ? 1.0 : i == multiple ? 0.5 : i == multiple + 1 ? 0.4 : 1.0 / (i + 1);
  auto diagonal = [&](const double *in, double *out, unsigned int k) {
    for (unsigned int c = 0; c < k; ++c)
      for (std::size_t i = 0; i < n; ++i) out[c * n + i] = d[i] * in[c * n + i];
  };
  for (const unsigned int block : {6u, 8u})
    {
      const auto pairs = reduction::block_lanczos(diagonal, n, multiple + 2, block, 100, 1e-12);
      ASSERT_TRUE(pairs.has_value()) << "block " << block;
      for (unsigned int j = 0; j < multiple + 2; ++j)
        EXPECT_NEAR(pairs->values[j], j < multiple ? 1.0 : j == multiple ? 0.5 : 0.4, 1e-12) << "block " << block;
      // The vectors of eigenvalue 1 span the first coordinates: their weight there is one each.
      double weight = 0;
      for (unsigned int j = 0; j < multiple; ++j)
        for (std::size_t i = 0; i < multiple; ++i) weight += std::pow(pairs->vectors[j * n + i], 2);
      EXPECT_NEAR(weight, multiple, 1e-10) << "block " << block;
    }

  // Eigenvalues 3, 3, 2, 2 and 1 (36 times): the Krylov space of a block of 4 is invariant after
  // two blocks (8 columns), so the third block vanishes in the orthogonalisation and is replaced
  // by fresh vectors (deflation). The 4 largest are exact there: to 1e-12, from a basis of 8.
  const std::size_t small = 40;
  auto few_distinct = [&](const double *in, double *out, unsigned int k) {
    for (unsigned int c = 0; c < k; ++c)
      for (std::size_t i = 0; i < small; ++i) out[c * small + i] = (i < 2 ? 3.0 : i < 4 ? 2.0 : 1.0) * in[c * small + i];
  };
  const auto pairs = reduction::block_lanczos(few_distinct, small, 4, 4, 32, 1e-12);
  ASSERT_TRUE(pairs.has_value());
  EXPECT_EQ(pairs->basis_size, 8u);
  const std::vector<double> expected{3.0, 3.0, 2.0, 2.0};
  for (unsigned int j = 0; j < 4; ++j) EXPECT_NEAR(pairs->values[j], expected[j], 1e-12);

  // Too small a basis allowed: no answer rather than an unconverged one.
  EXPECT_FALSE(reduction::block_lanczos(
                 [&](const double *in, double *out, unsigned int k) { inverse_laplacian(in, out, k, 3000); }, 3000, 10, 4,
                 16, 1e-12)
                 .has_value());
}
