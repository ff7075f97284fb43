// Narrower supernodes (reduction/supernode_width.h) against CHOLMOD's own supernodal factor of
// the same matrix: the same L to round-off, in fewer stored numbers.
#include <reduction/supernode_width.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <new>
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
      for (const auto &[ok, step] : {std::pair{x + 1 < m, 1}, std::pair{y + 1 < m, m}, std::pair{z + 1 < m, m * m}})
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
/// The widest supernode of @p L.
std::size_t widest_supernode(const cholmod_factor *L)
{
  const auto *super = static_cast<const int *>(L->super);
  std::size_t w = 0;
  for (std::size_t k = 0; k < L->nsuper; ++k) w = std::max<std::size_t>(w, super[k + 1] - super[k]);
  return w;
}

/// CHOLMOD's update workspace by its definition, pair by pair: for every supernode d and every
/// supernode s that one of d's rows below its diagonal block falls into, (rows of d in s's
/// columns) x (rows of d from s's first column on).
std::size_t largest_update_pair_by_pair(const cholmod_factor *L)
{
  const auto *super = static_cast<const int *>(L->super), *pi = static_cast<const int *>(L->pi);
  const auto *rows = static_cast<const int *>(L->s);
  std::size_t largest = 1;
  for (std::size_t d = 0; d < L->nsuper; ++d)
    {
      const int below = pi[d] + super[d + 1] - super[d];
      for (std::size_t s = d + 1; s < L->nsuper; ++s)
        {
          std::size_t in_s = 0, from_s = 0;
          for (int p = below; p < pi[d + 1]; ++p)
            {
              in_s += rows[p] >= super[s] && rows[p] < super[s + 1];
              from_s += rows[p] >= super[s];
            }
          largest = std::max(largest, in_s * from_s);
        }
    }
  return largest;
}

/// A malloc that fails after a given number of successful calls (out of memory on purpose).
int mallocs_left = 0;
void *failing_malloc(const std::size_t size) { return mallocs_left-- > 0 ? std::malloc(size) : nullptr; }
} // namespace

TEST(SupernodeWidth, split_factor_equals_cholmods_factor_in_fewer_numbers)
{
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  cholmod_sparse *A = grid_laplacian(22, common); // 10 648 unknowns
  cholmod_factor *reference = cholmod_analyze(A, &common);
  ASSERT_TRUE(reference && reference->is_super) << "the test needs a supernodal factor";
  cholmod_factor *split = cholmod_copy_factor(reference, &common);
  ASSERT_GT(widest_supernode(reference), 100u) << "the separators should give wide supernodes";

  // The workspace sizes as this code computes them, against CHOLMOD's own (exact).
  const reduction::SupernodeWorkspace own = reduction::supernode_workspace(*reference);
  EXPECT_EQ(own.max_update, reference->maxcsize);
  EXPECT_EQ(own.max_rows_below, reference->maxesize);

  // Nothing to split: no change.
  for (const std::size_t no_cap : {std::size_t(0), widest_supernode(reference), std::size_t(-1)})
    {
      const reduction::SupernodeSplit same = reduction::cap_supernode_width(*split, no_cap, common);
      EXPECT_EQ(same.supernodes_after, reference->nsuper) << "cap " << no_cap;
      EXPECT_EQ(split->xsize, reference->xsize) << "cap " << no_cap;
    }

  // Out of memory at the first and at the last of the four new arrays: an exception, the factor
  // as it was, and what was allocated freed (CHOLMOD's memory count, checked at the end).
  for (const int succeeding : {0, 3})
    {
      const auto system_malloc = SuiteSparse_config.malloc_func;
      SuiteSparse_config.malloc_func = failing_malloc;
      mallocs_left = succeeding;
      EXPECT_THROW(reduction::cap_supernode_width(*split, 32, common), std::bad_alloc);
      SuiteSparse_config.malloc_func = system_malloc;
      EXPECT_EQ(split->nsuper, reference->nsuper);
      EXPECT_EQ(split->xsize, reference->xsize);
      common.status = CHOLMOD_OK;
    }

  const std::size_t cap = 32;
  const reduction::SupernodeSplit s = reduction::cap_supernode_width(*split, cap, common);
  EXPECT_EQ(s.supernodes_before, reference->nsuper);
  EXPECT_GT(s.supernodes_after, s.supernodes_before);
  EXPECT_EQ(s.supernodes_after, split->nsuper);
  EXPECT_EQ(s.numbers_after, split->xsize);
  const auto *super = static_cast<const int *>(split->super);
  for (std::size_t k = 0; k < split->nsuper; ++k) EXPECT_LE(super[k + 1] - super[k], static_cast<int>(cap));
  EXPECT_TRUE(cholmod_check_factor(split, &common)) << "CHOLMOD's own consistency check of the split factor";
  EXPECT_EQ(split->maxcsize, largest_update_pair_by_pair(split));
  EXPECT_LT(split->maxcsize, reference->maxcsize);
  EXPECT_EQ(split->maxesize, reduction::supernode_workspace(*split).max_rows_below);

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

  // Solves with the split factor, three right-hand sides at once (CHOLMOD's solve workspace is
  // sized by maxesize and their number): b = A X with the columns of X = 1, 2, 3, so the error
  // of X is the residual, bounded by cond(A) < 13 (eigenvalues of 7 I + grid Laplacian within
  // [1, 13]) times round-off.
  const std::size_t n = A->nrow;
  cholmod_dense *X = cholmod_zeros(n, 3, CHOLMOD_REAL, &common);
  for (std::size_t c = 0; c < 3; ++c)
    std::fill_n(static_cast<double *>(X->x) + c * n, n, 1.0 + c);
  cholmod_dense *b = cholmod_zeros(n, 3, CHOLMOD_REAL, &common);
  double alpha[2] = {1, 0}, beta[2] = {0, 0};
  cholmod_sdmult(A, false, alpha, beta, X, b, &common);
  cholmod_dense *x = cholmod_solve(CHOLMOD_A, split, b, &common);
  double error = 0;
  for (std::size_t e = 0; e < 3 * n; ++e)
    error = std::max(error, std::abs(static_cast<double *>(x->x)[e] - static_cast<double *>(X->x)[e]));
  EXPECT_LT(error, 1e-12);

  for (cholmod_dense *d : {X, b, x}) cholmod_free_dense(&d, &common);
  for (cholmod_sparse *m : {A, l_ref, l_split}) cholmod_free_sparse(&m, &common);
  cholmod_free_factor(&reference, &common);
  cholmod_free_factor(&split, &common);
  cholmod_free_work(&common); // CHOLMOD's own workspace, kept in common
  EXPECT_EQ(common.memory_inuse, 0u) << "every array freed with the size it was allocated with";
  cholmod_finish(&common);
}
