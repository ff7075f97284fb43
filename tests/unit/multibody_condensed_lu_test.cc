// CondensedLU (multibody/condensed_lu.h): the dense LU with the leading unknowns condensed out
// through their small diagonal blocks. Reference: a manufactured solution x (b = A x), which the
// solve must return to round-off, and LAPACK's LU of the whole matrix (dgetrf/dgetrs).
#include <multibody/condensed_lu.h>
#include <multibody/lapack.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

using flextrack::multibody::CondensedResult;
using CondensedLU = flextrack::multibody::CondensedLU<double>;

namespace
{
/// A column-major n x n matrix whose first m unknowns couple among themselves only within the
/// given blocks (interleaved, as a body's R and p are not next to each other in general), with
/// a diagonal of 50 in those blocks (cj I dominates a Newton matrix's position rows) and random
/// entries elsewhere. @p swapped: the 50 on each block's anti-diagonal instead, so that the
/// block's LU swaps rows at every step (as a frame's block does when h |omega| is of order 1).
std::vector<double> matrix_with_blocks(const unsigned int n, const unsigned int m,
                                       const std::vector<std::vector<unsigned int>> &blocks, std::mt19937 &rng,
                                       const bool swapped = false)
{
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> a(std::size_t(n) * n);
  const auto at = [&](unsigned int r, unsigned int c) -> double & { return a[std::size_t(c) * n + r]; };
  for (unsigned int c = 0; c < n; ++c)
    for (unsigned int r = 0; r < n; ++r)
      if (r >= m || c >= m) at(r, c) = u(rng);
  for (unsigned int r = m; r < n; ++r) at(r, r) += 5;
  std::vector<bool> in_block(m, false);
  for (const auto &block : blocks)
    for (unsigned int i = 0; i < block.size(); ++i)
      {
        in_block[block[i]] = true;
        for (unsigned int k = 0; k < block.size(); ++k)
          at(block[i], block[k]) = ((swapped ? i + k + 1 == block.size() : i == k) ? 50 : 0) + u(rng);
      }
  for (unsigned int r = 0; r < m; ++r)
    if (!in_block[r]) at(r, r) = 50 + u(rng);
  return a;
}

std::vector<double> times(const std::vector<double> &a, const std::vector<double> &x)
{
  const std::size_t n = x.size();
  std::vector<double> b(n, 0.0);
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t r = 0; r < n; ++r) b[r] += a[c * n + r] * x[c];
  return b;
}

double largest_difference(const std::vector<double> &x, const std::vector<double> &y)
{
  double d = 0;
  for (std::size_t i = 0; i < x.size(); ++i) d = std::max(d, std::abs(x[i] - y[i]));
  return d;
}
} // namespace

TEST(CondensedLU, solves_with_uncoupled_position_blocks_as_the_whole_lu_does)
{
  // 40 unknowns, the first 18 in a block of 7 (like a body's R and p), one of 4 and 7 alone;
  // the blocks diagonally dominant, and with their large entries on the anti-diagonal (row swaps
  // at every step of the blocks' LU).
  for (const bool swapped : {false, true})
  {
  SCOPED_TRACE(swapped ? "blocks that need row swaps" : "diagonally dominant blocks");
  const unsigned int n = 40, m = 18;
  std::mt19937 rng(3);
  const std::vector<std::vector<unsigned int>> blocks = {{0, 3, 5, 8, 11, 14, 17}, {1, 4, 9, 16}};
  std::vector<double> a = matrix_with_blocks(n, m, blocks, rng, swapped), whole = a;
  std::vector<double> x(n);
  for (unsigned int i = 0; i < n; ++i) x[i] = std::sin(0.7 * i + 0.2);
  const std::vector<double> b = times(a, x);

  CondensedLU lu;
  ASSERT_EQ(lu.factorize(a.data(), n, m), CondensedResult::factored);
  EXPECT_EQ(lu.complement_size(), n - m);
  std::vector<double> condensed = b;
  lu.solve(a.data(), condensed.data());

  const int N = n, one = 1;
  std::vector<int> pivots(n);
  int info = 0;
  dgetrf_(&N, &N, whole.data(), &N, pivots.data(), &info);
  ASSERT_EQ(info, 0);
  std::vector<double> reference = b;
  dgetrs_("N", &N, &one, whole.data(), &N, pivots.data(), reference.data(), &N, &info);
  ASSERT_EQ(info, 0);
  // Both to the manufactured x within round-off (|x| <= 1, condition number of order 100):
  // 1e-12; and to each other.
  EXPECT_LT(largest_difference(condensed, x), 1e-12);
  EXPECT_LT(largest_difference(reference, x), 1e-12);
  EXPECT_LT(largest_difference(condensed, reference), 1e-12);
  }
}

TEST(CondensedLU, leaves_coupled_or_singular_position_blocks_to_the_whole_lu)
{
  const unsigned int n = 20, m = 10;
  std::mt19937 rng(5);
  CondensedLU lu;
  {
    // The first 9 unknowns coupled in a chain (a block of 9 > max_block = 8): not applicable,
    // and the matrix left as it was.
    std::vector<double> a = matrix_with_blocks(n, m, {}, rng);
    for (unsigned int i = 0; i + 1 < 9; ++i) a[std::size_t(i + 1) * n + i] = 0.5;
    const std::vector<double> before = a;
    EXPECT_EQ(lu.factorize(a.data(), n, m), CondensedResult::not_applicable);
    EXPECT_EQ(a, before);
  }
  {
    // A zero position block (a static solve: cj = 0 and no d(T v)/dq in a modal row).
    std::vector<double> a = matrix_with_blocks(n, m, {}, rng);
    a[std::size_t(4) * n + 4] = 0;
    const std::vector<double> before = a;
    EXPECT_EQ(lu.factorize(a.data(), n, m), CondensedResult::not_applicable);
    EXPECT_EQ(a, before);
  }
  {
    // A zero row among the rest: the matrix is singular, and the complement's row is exactly zero
    // too (two equal rows made it singular only up to the rounding of the LU's blocked updates).
    std::vector<double> a = matrix_with_blocks(n, m, {{0, 1}}, rng);
    for (unsigned int c = 0; c < n; ++c) a[std::size_t(c) * n + 15] = 0;
    EXPECT_EQ(lu.factorize(a.data(), n, m), CondensedResult::singular);
  }
}

TEST(CondensedLU, solves_a_complex_matrix_as_the_whole_lu_does)
{
  // Radau IIA's complex Newton matrix J + (alpha - i beta) / h M: the same structure with complex
  // entries (real part and 0.3 i times a second matrix of the same blocks). Reference: LAPACK's
  // zgetrf/zgetrs of the whole matrix and the manufactured x; tolerance 1e-12 as above.
  using Complex = std::complex<double>;
  const unsigned int n = 30, m = 12;
  std::mt19937 rng(9);
  const std::vector<std::vector<unsigned int>> blocks = {{0, 2, 4, 6, 8, 10, 11}, {1, 3}};
  // The real part's blocks need row swaps (anti-diagonal), as in the real test's second case.
  const std::vector<double> re = matrix_with_blocks(n, m, blocks, rng, true), im = matrix_with_blocks(n, m, blocks, rng);
  std::vector<Complex> a(re.size()), x(n), b(n, 0.0);
  for (std::size_t k = 0; k < a.size(); ++k) a[k] = Complex(re[k], 0.3 * im[k]);
  for (unsigned int i = 0; i < n; ++i) x[i] = Complex(std::sin(0.4 * i), std::cos(0.9 * i));
  for (unsigned int c = 0; c < n; ++c)
    for (unsigned int r = 0; r < n; ++r) b[r] += a[std::size_t(c) * n + r] * x[c];
  std::vector<Complex> whole = a, condensed = b, reference = b;

  flextrack::multibody::CondensedLU<Complex> lu;
  ASSERT_EQ(lu.factorize(a.data(), n, m), CondensedResult::factored);
  lu.solve(a.data(), condensed.data());
  const int N = n, one = 1;
  std::vector<int> pivots(n);
  int info = 0;
  zgetrf_(&N, &N, whole.data(), &N, pivots.data(), &info);
  ASSERT_EQ(info, 0);
  zgetrs_("N", &N, &one, whole.data(), &N, pivots.data(), reference.data(), &N, &info);
  ASSERT_EQ(info, 0);
  double to_x = 0, to_reference = 0;
  for (unsigned int i = 0; i < n; ++i)
    to_x = std::max(to_x, std::abs(condensed[i] - x[i])), to_reference = std::max(to_reference, std::abs(condensed[i] - reference[i]));
  EXPECT_LT(to_x, 1e-12);
  EXPECT_LT(to_reference, 1e-12);
}
