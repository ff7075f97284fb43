// Dense LU with the leading unknowns condensed out through small blocks (condensed_lu.h).
#include <multibody/condensed_lu.h>
#include <multibody/lapack.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace flextrack::multibody
{
namespace
{
unsigned int root(std::vector<unsigned int> &parent, unsigned int i)
{
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/// LU with partial pivoting of the k x k row-major block @p a in place; false if a pivot is
/// below 1e-8 of the block's largest entry: such a block is left to the full LU, whose pivoting
/// ranges over all unknowns.
bool small_lu(double *a, const unsigned int k, int *pivots)
{
  double largest = 0;
  for (unsigned int i = 0; i < k * k; ++i) largest = std::max(largest, std::abs(a[i]));
  for (unsigned int c = 0; c < k; ++c)
    {
      unsigned int p = c;
      for (unsigned int r = c + 1; r < k; ++r)
        if (std::abs(a[r * k + c]) > std::abs(a[p * k + c])) p = r;
      if (!(std::abs(a[p * k + c]) > 1e-8 * largest)) return false;
      pivots[c] = p;
      if (p != c)
        for (unsigned int j = 0; j < k; ++j) std::swap(a[c * k + j], a[p * k + j]);
      for (unsigned int r = c + 1; r < k; ++r)
        {
          const double f = a[r * k + c] /= a[c * k + c];
          for (unsigned int j = c + 1; j < k; ++j) a[r * k + j] -= f * a[c * k + j];
        }
    }
  return true;
}

/// b = (LU)^{-1} b for the factors of small_lu().
void small_solve(const double *a, const unsigned int k, const int *pivots, double *b)
{
  for (unsigned int c = 0; c < k; ++c)
    {
      std::swap(b[c], b[pivots[c]]);
      for (unsigned int r = c + 1; r < k; ++r) b[r] -= a[r * k + c] * b[c];
    }
  for (unsigned int c = k; c-- > 0;)
    {
      for (unsigned int j = c + 1; j < k; ++j) b[c] -= a[c * k + j] * b[j];
      b[c] /= a[c * k + c];
    }
}
} // namespace

CondensedLU::Result CondensedLU::factorize(double *a, const unsigned int n_, const unsigned int n_leading)
{
  n = n_, n_lead = n_leading;
  const unsigned int m = n_lead;
  const auto at = [&](const unsigned int row, const unsigned int col) -> double & { return a[std::size_t(col) * n + row]; };

  // The leading unknowns coupled by a nonzero entry of G_QQ form one block.
  std::vector<unsigned int> parent(m);
  std::iota(parent.begin(), parent.end(), 0u);
  for (unsigned int j = 0; j < m; ++j)
    for (unsigned int i = 0; i < m; ++i)
      if (i != j && at(i, j) != 0) parent[root(parent, i)] = root(parent, j);
  std::vector<unsigned int> block_of(m), size;
  std::vector<int> block_of_root(m, -1);
  for (unsigned int i = 0; i < m; ++i)
    {
      const unsigned int r = root(parent, i);
      if (block_of_root[r] < 0) block_of_root[r] = size.size(), size.push_back(0);
      block_of[i] = block_of_root[r];
      if (++size[block_of[i]] > max_block) return Result::not_applicable;
    }
  const unsigned int n_blocks = size.size();
  block_start.assign(n_blocks + 1, 0);
  block_factor_start.assign(n_blocks + 1, 0);
  for (unsigned int b = 0; b < n_blocks; ++b)
    {
      block_start[b + 1] = block_start[b] + size[b];
      block_factor_start[b + 1] = block_factor_start[b] + size[b] * size[b];
    }
  block_members.resize(m);
  std::vector<unsigned int> fill(block_start.begin(), block_start.end() - 1);
  for (unsigned int i = 0; i < m; ++i) block_members[fill[block_of[i]]++] = i;

  // Each block's LU; nothing of a is changed before all of them succeed.
  block_factors.resize(block_factor_start.back());
  block_pivots.resize(m);
  for (unsigned int b = 0; b < n_blocks; ++b)
    {
      const unsigned int k = size[b], *members = block_members.data() + block_start[b];
      double *f = block_factors.data() + block_factor_start[b];
      for (unsigned int r = 0; r < k; ++r)
        for (unsigned int c = 0; c < k; ++c) f[r * k + c] = at(members[r], members[c]);
      if (!small_lu(f, k, block_pivots.data() + block_start[b])) return Result::not_applicable;
    }

  // C = G_QQ^{-1} G_QR over G_QR, S = G_RR - G_RQ C over G_RR, then S's LU.
  const int rest = n - m, lead = m, ld = n;
  solve_blocks(a + std::size_t(m) * n, rest, n);
  const double minus_one = -1, one = 1;
  if (rest > 0 && lead > 0)
    dgemm_("N", "N", &rest, &rest, &lead, &minus_one, a + m, &ld, a + std::size_t(m) * n, &ld, &one,
           a + std::size_t(m) * n + m, &ld);
  complement_pivots.resize(rest);
  int info = 0;
  if (rest > 0) dgetrf_(&rest, &rest, a + std::size_t(m) * n + m, &ld, complement_pivots.data(), &info);
  if (info < 0) throw std::logic_error("LAPACK dgetrf: argument " + std::to_string(-info) + " is invalid");
  return info == 0 ? Result::factored : Result::singular;
}

void CondensedLU::solve_blocks(double *x, const unsigned int columns, const unsigned int ld) const
{
  double b[max_block];
  for (unsigned int k = 0; k + 1 < block_start.size(); ++k)
    {
      const unsigned int size = block_start[k + 1] - block_start[k], *members = block_members.data() + block_start[k];
      const double *f = block_factors.data() + block_factor_start[k];
      if (size == 1) // most blocks: a modal or track coordinate alone
        {
          const double d = f[0];
          for (unsigned int c = 0; c < columns; ++c) x[std::size_t(c) * ld + members[0]] /= d;
          continue;
        }
      for (unsigned int c = 0; c < columns; ++c)
        {
          double *column = x + std::size_t(c) * ld;
          for (unsigned int r = 0; r < size; ++r) b[r] = column[members[r]];
          small_solve(f, size, block_pivots.data() + block_start[k], b);
          for (unsigned int r = 0; r < size; ++r) column[members[r]] = b[r];
        }
    }
}

void CondensedLU::solve(const double *a, double *x) const
{
  const int rest = n - n_lead, lead = n_lead, ld = n, one_step = 1;
  const double minus_one = -1, one = 1;
  solve_blocks(x, 1, n); // y_Q = G_QQ^{-1} b_Q
  double *x_rest = x + n_lead;
  if (rest > 0 && lead > 0) // b_R - G_RQ y_Q
    dgemv_("N", &rest, &lead, &minus_one, a + n_lead, &ld, x, &one_step, &one, x_rest, &one_step);
  int info = 0;
  if (rest > 0)
    dgetrs_("N", &rest, &one_step, a + std::size_t(n_lead) * n + n_lead, &ld, complement_pivots.data(), x_rest, &rest, &info);
  if (info != 0) throw std::runtime_error("LAPACK could not solve with the condensed Jacobian (dgetrs status " + std::to_string(info) + ")");
  if (rest > 0 && lead > 0) // x_Q = y_Q - C x_R
    dgemv_("N", &lead, &rest, &minus_one, a + std::size_t(n_lead) * n, &ld, x_rest, &one_step, &one, x, &one_step);
}
} // namespace flextrack::multibody
