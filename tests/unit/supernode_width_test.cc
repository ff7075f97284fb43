// Narrower supernodes (reduction/supernode_width.h) against CHOLMOD's own supernodal factor of
// the same matrix: the same L to round-off, in fewer stored numbers.
#include <reduction/supernode_width.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace flextrack;

namespace
{
/// The 7-point Laplacian of an m^3 grid plus the identity (positive definite), lower triangle:
/// its nested-dissection separators make supernodes of up to m^2 columns.
cholmod_sparse *grid_laplacian(const int m, cholmod_common &common)
{
  const int n = m * m * m;
  cholmod_sparse *A = cholmod_allocate_sparse(n, n, 4 * n, true, true, -1, CHOLMOD_REAL, &common);
  auto *start = static_cast<int *>(A->p), *rows = static_cast<int *>(A->i);
  auto *values = static_cast<double *>(A->x);
  int e = 0;
  for (int j = 0; j < n; ++j)
    {
      start[j] = e;
      rows[e] = j;
      values[e++] = 7.0;
      const int x = j % m, y = j / m % m, z = j / (m * m);
      for (const auto [ok, step] : {std::pair{x + 1 < m, 1}, std::pair{y + 1 < m, m}, std::pair{z + 1 < m, m * m}})
        if (ok)
          {
            rows[e] = j + step;
            values[e++] = -1.0;
          }
    }
  start[n] = e;
  return A;
}

/// L's stored columns as one sparse matrix (the pattern and values CHOLMOD computed).
cholmod_sparse *factor_columns(const cholmod_factor *L, cholmod_common &common)
{
  cholmod_factor *copy = cholmod_copy_factor(const_cast<cholmod_factor *>(L), &common);
  cholmod_sparse *columns = cholmod_factor_to_sparse(copy, &common);
  cholmod_free_factor(&copy, &common);
  return columns;
}
} // namespace

TEST(SupernodeWidth, split_factor_equals_cholmods_factor_in_fewer_numbers)
{
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  cholmod_sparse *A = grid_laplacian(22, common); // 10 648 unknowns
  cholmod_factor *reference = cholmod_analyze(A, &common);
  cholmod_factor *split = cholmod_copy_factor(reference, &common);
  ASSERT_TRUE(reference && reference->is_super) << "the test needs a supernodal factor";
  const std::size_t widest = [&] {
    const auto *super = static_cast<const int *>(reference->super);
    std::size_t w = 0;
    for (std::size_t k = 0; k < reference->nsuper; ++k) w = std::max<std::size_t>(w, super[k + 1] - super[k]);
    return w;
  }();
  ASSERT_GT(widest, 100u) << "the separators should give wide supernodes";

  const std::size_t cap = 32;
  const reduction::SupernodeSplit s = reduction::cap_supernode_width(*split, cap, common);
  EXPECT_EQ(s.supernodes_before, reference->nsuper);
  EXPECT_GT(s.supernodes_after, s.supernodes_before);
  EXPECT_EQ(s.supernodes_after, split->nsuper);
  EXPECT_EQ(s.numbers_after, split->xsize);
  const auto *super = static_cast<const int *>(split->super);
  for (std::size_t k = 0; k < split->nsuper; ++k) EXPECT_LE(super[k + 1] - super[k], static_cast<int>(cap));
  EXPECT_TRUE(cholmod_check_factor(split, &common)) << "CHOLMOD's own consistency check of the split factor";

  cholmod_factorize(A, reference, &common);
  ASSERT_EQ(common.status, CHOLMOD_OK);
  cholmod_factorize(A, split, &common);
  ASSERT_EQ(common.status, CHOLMOD_OK);

  // Same columns of L: the same pattern, the same values up to the order of summation. Bound
  // 1e-13 of max |L_ij| (entries are sums of at most a few hundred products of size <= 3).
  cholmod_sparse *l_ref = factor_columns(reference, common), *l_split = factor_columns(split, common);
  ASSERT_EQ(l_ref->nzmax, l_split->nzmax);
  const auto *p_ref = static_cast<const int *>(l_ref->p), *p_split = static_cast<const int *>(l_split->p);
  const auto *i_ref = static_cast<const int *>(l_ref->i), *i_split = static_cast<const int *>(l_split->i);
  const auto *x_ref = static_cast<const double *>(l_ref->x), *x_split = static_cast<const double *>(l_split->x);
  double largest = 0, difference = 0;
  bool same_pattern = true;
  for (std::size_t j = 0; j <= A->ncol; ++j) same_pattern = same_pattern && p_ref[j] == p_split[j];
  ASSERT_TRUE(same_pattern);
  for (int e = 0; e < p_ref[A->ncol]; ++e)
    {
      same_pattern = same_pattern && i_ref[e] == i_split[e];
      largest = std::max(largest, std::abs(x_ref[e]));
      difference = std::max(difference, std::abs(x_ref[e] - x_split[e]));
    }
  EXPECT_TRUE(same_pattern);
  EXPECT_LT(difference, 1e-13 * largest);

  // The stored numbers: L's entries plus the strict upper half of each supernode's diagonal
  // block, counted independently of the split's own bookkeeping.
  auto unused_half = [](const cholmod_factor *L) {
    const auto *sup = static_cast<const int *>(L->super);
    std::size_t u = 0;
    for (std::size_t k = 0; k < L->nsuper; ++k)
      {
        const std::size_t w = sup[k + 1] - sup[k];
        u += w * (w - 1) / 2;
      }
    return u;
  };
  const std::size_t entries = p_ref[A->ncol];
  EXPECT_EQ(s.numbers_before, entries + unused_half(reference));
  EXPECT_EQ(s.numbers_after, entries + unused_half(split));
  std::cout << "  " << s.supernodes_before << " -> " << s.supernodes_after << " supernodes, " << s.numbers_before
            << " -> " << s.numbers_after << " stored numbers (" << entries << " entries of L), max |dL| " << difference
            << '\n';

  // A solve with the split factor: the residual of A x = b (b = A 1 gives x = 1).
  cholmod_dense *ones = cholmod_ones(A->nrow, 1, CHOLMOD_REAL, &common);
  cholmod_dense *b = cholmod_zeros(A->nrow, 1, CHOLMOD_REAL, &common);
  double alpha[2] = {1, 0}, beta[2] = {0, 0};
  cholmod_sdmult(A, false, alpha, beta, ones, b, &common);
  cholmod_dense *x = cholmod_solve(CHOLMOD_A, split, b, &common);
  double error = 0;
  for (std::size_t i = 0; i < A->nrow; ++i) error = std::max(error, std::abs(static_cast<double *>(x->x)[i] - 1.0));
  EXPECT_LT(error, 1e-12); // cond(A) < 2 (eigenvalues of 7 I + grid Laplacian within [1, 13])

  for (cholmod_dense *d : {ones, b, x}) cholmod_free_dense(&d, &common);
  for (cholmod_sparse *m : {A, l_ref, l_split}) cholmod_free_sparse(&m, &common);
  cholmod_free_factor(&reference, &common);
  cholmod_free_factor(&split, &common);
  cholmod_finish(&common);
}
