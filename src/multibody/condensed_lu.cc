// Dense LU with the leading unknowns condensed out through small blocks (condensed_lu.h).
#include <multibody/condensed_lu.h>
#include <multibody/lapack.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numeric>
#include <stdexcept>
#include <string>

namespace flextrack::multibody
{
namespace
{
using Complex = std::complex<double>;

// BLAS and LAPACK by scalar type.
void gemv(const int m, const int n, const double *a, const int lda, const double *x, double *y) // y -= a x
{
  const double minus_one = -1, one = 1;
  const int step = 1;
  dgemv_("N", &m, &n, &minus_one, a, &lda, x, &step, &one, y, &step);
}
void gemv(const int m, const int n, const Complex *a, const int lda, const Complex *x, Complex *y)
{
  const Complex minus_one = -1, one = 1;
  const int step = 1;
  zgemv_("N", &m, &n, &minus_one, a, &lda, x, &step, &one, y, &step);
}
int getrf(const int n, double *a, const int lda, int *pivots)
{
  int info = 0;
  dgetrf_(&n, &n, a, &lda, pivots, &info);
  return info;
}
int getrf(const int n, Complex *a, const int lda, int *pivots)
{
  int info = 0;
  zgetrf_(&n, &n, a, &lda, pivots, &info);
  return info;
}
int getrs(const int n, const double *a, const int lda, const int *pivots, double *x)
{
  const int one = 1;
  int info = 0;
  dgetrs_("N", &n, &one, a, &lda, pivots, x, &n, &info);
  return info;
}
int getrs(const int n, const Complex *a, const int lda, const int *pivots, Complex *x)
{
  const int one = 1;
  int info = 0;
  zgetrs_("N", &n, &one, a, &lda, pivots, x, &n, &info);
  return info;
}

// y -= c x over n entries, and x *= c. std::complex's operator* checks for infinities and NaNs
// through libgcc's __muldc3 on every product (without -fcx-limited-range), which made the
// complex loops slower than zgemm over the dense matrix: written out on the parts instead (the
// standard lets a complex<double> array be read as its real and imaginary parts).
void subtract_multiple(const double c, const double *x, double *y, const unsigned int n)
{
  for (unsigned int r = 0; r < n; ++r) y[r] -= c * x[r];
}
void subtract_multiple(const Complex c, const Complex *x, Complex *y, const unsigned int n)
{
  const double cr = c.real(), ci = c.imag(), *xd = reinterpret_cast<const double *>(x);
  double *yd = reinterpret_cast<double *>(y);
  for (unsigned int r = 0; r < n; ++r)
    {
      const double xr = xd[2 * r], xi = xd[2 * r + 1];
      yd[2 * r] -= cr * xr - ci * xi;
      yd[2 * r + 1] -= cr * xi + ci * xr;
    }
}
void scale(double &x, const double c) { x *= c; }
void scale(Complex &x, const Complex c)
{
  const double xr = x.real(), xi = x.imag();
  x = Complex(xr * c.real() - xi * c.imag(), xr * c.imag() + xi * c.real());
}

unsigned int root(std::vector<unsigned int> &parent, unsigned int i)
{
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/// LU with partial pivoting of the k x k row-major block @p a in place; false if a pivot is
/// below 1e-8 of the block's largest entry: such a block is left to the full LU, whose pivoting
/// ranges over all unknowns.
template <typename Number>
bool small_lu(Number *a, const unsigned int k, int *pivots)
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
          const Number f = a[r * k + c] /= a[c * k + c];
          for (unsigned int j = c + 1; j < k; ++j) a[r * k + j] -= f * a[c * k + j];
        }
    }
  return true;
}

/// b = (LU)^{-1} b for the factors of small_lu(). Its swaps moved whole rows, the multipliers
/// already stored included (as LAPACK's), so P b comes first, then the forward substitution.
template <typename Number>
void small_solve(const Number *a, const unsigned int k, const int *pivots, Number *b)
{
  for (unsigned int c = 0; c < k; ++c) std::swap(b[c], b[pivots[c]]);
  for (unsigned int c = 0; c < k; ++c)
    for (unsigned int r = c + 1; r < k; ++r) b[r] -= a[r * k + c] * b[c];
  for (unsigned int c = k; c-- > 0;)
    {
      for (unsigned int j = c + 1; j < k; ++j) b[c] -= a[c * k + j] * b[j];
      b[c] /= a[c * k + c];
    }
}
} // namespace

template <typename Number>
CondensedResult CondensedLU<Number>::factorize(Number *a, const unsigned int n_, const unsigned int n_leading)
{
  n = n_, n_lead = n_leading;
  const unsigned int m = n_lead;
  const auto at = [&](const unsigned int row, const unsigned int col) -> Number & { return a[std::size_t(col) * n + row]; };

  // The leading unknowns coupled by a nonzero entry of G_QQ form one block.
  std::vector<unsigned int> parent(m);
  std::iota(parent.begin(), parent.end(), 0u);
  for (unsigned int j = 0; j < m; ++j)
    for (unsigned int i = 0; i < m; ++i)
      if (i != j && at(i, j) != Number(0)) parent[root(parent, i)] = root(parent, j);
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
      Number *f = block_factors.data() + block_factor_start[b];
      for (unsigned int r = 0; r < k; ++r)
        for (unsigned int c = 0; c < k; ++c) f[r * k + c] = at(members[r], members[c]);
      if (!small_lu(f, k, block_pivots.data() + block_start[b])) return Result::not_applicable;
      if (k == 1) f[0] = Number(1) / f[0]; // a 1 x 1 block keeps its reciprocal (solve_blocks)
    }

  // C = G_QQ^{-1} G_QR over G_QR, S = G_RR - G_RQ C over G_RR, then S's LU.
  const int rest = n - m, ld = n;
  solve_blocks(a + std::size_t(m) * n, rest, n);
  // S = G_RR - G_RQ C column by column over C's nonzeros only: a position row couples to few
  // columns of the rest (its body's velocities through T, the multipliers of its joints), so C
  // is mostly zero, and a dense gemm over it cost as much as the LU of S (Radau's complex
  // matrix of the double-arm sleeve: 1.6e9 of 10e9 instructions).
  for (unsigned int j = 0; j < static_cast<unsigned int>(rest); ++j)
    {
      const Number *c_j = a + std::size_t(m + j) * n;
      Number *s_j = a + std::size_t(m + j) * n + m;
      for (unsigned int k = 0; k < m; ++k)
        if (c_j[k] != Number(0)) subtract_multiple(c_j[k], a + std::size_t(k) * n + m, s_j, rest); // G_RQ's column k
    }
  complement_pivots.resize(rest);
  const int info = rest > 0 ? getrf(rest, a + std::size_t(m) * n + m, ld, complement_pivots.data()) : 0;
  if (info < 0) throw std::logic_error("LAPACK getrf: argument " + std::to_string(-info) + " is invalid");
  return info == 0 ? Result::factored : Result::singular;
}

template <typename Number>
void CondensedLU<Number>::solve_blocks(Number *x, const unsigned int columns, const unsigned int ld) const
{
  Number b[max_block];
  for (unsigned int k = 0; k + 1 < block_start.size(); ++k)
    {
      const unsigned int size = block_start[k + 1] - block_start[k], *members = block_members.data() + block_start[k];
      const Number *f = block_factors.data() + block_factor_start[k];
      if (size == 1) // most blocks: a modal or track coordinate alone; f holds its reciprocal
        {
          const Number inverse = f[0];
          for (unsigned int c = 0; c < columns; ++c) scale(x[std::size_t(c) * ld + members[0]], inverse);
          continue;
        }
      for (unsigned int c = 0; c < columns; ++c)
        {
          Number *column = x + std::size_t(c) * ld;
          for (unsigned int r = 0; r < size; ++r) b[r] = column[members[r]];
          small_solve(f, size, block_pivots.data() + block_start[k], b);
          for (unsigned int r = 0; r < size; ++r) column[members[r]] = b[r];
        }
    }
}

template <typename Number>
void CondensedLU<Number>::solve(const Number *a, Number *x) const
{
  const int rest = n - n_lead, lead = n_lead, ld = n;
  solve_blocks(x, 1, n); // y_Q = G_QQ^{-1} b_Q
  Number *x_rest = x + n_lead;
  if (rest > 0 && lead > 0) gemv(rest, lead, a + n_lead, ld, x, x_rest); // b_R - G_RQ y_Q
  const int info = rest > 0 ? getrs(rest, a + std::size_t(n_lead) * n + n_lead, ld, complement_pivots.data(), x_rest) : 0;
  if (info != 0) throw std::runtime_error("LAPACK could not solve with the condensed Jacobian (getrs status " + std::to_string(info) + ")");
  if (rest > 0 && lead > 0) gemv(lead, rest, a + std::size_t(n_lead) * n, ld, x_rest, x); // x_Q = y_Q - C x_R
}

template <typename Number>
bool NewtonLU<Number>::factorize(Number *a, const unsigned int n_, const unsigned int n_condensed)
{
  n = n_;
  used_condensed = false;
  if (n_condensed > 0)
    switch (condensed_lu.factorize(a, n, n_condensed))
      {
        case CondensedResult::factored:
          return used_condensed = true;
        case CondensedResult::singular:
          return false;
        case CondensedResult::not_applicable:
          break; // the whole matrix, unchanged, below
      }
  pivots.resize(n);
  const int info = n > 0 ? getrf(n, a, n, pivots.data()) : 0;
  if (info < 0) throw std::logic_error("LAPACK getrf: argument " + std::to_string(-info) + " is invalid");
  return info == 0; // info > 0: an exactly zero pivot, the matrix is singular
}

template <typename Number>
void NewtonLU<Number>::solve(const Number *a, Number *x) const
{
  if (used_condensed) return condensed_lu.solve(a, x);
  const int info = n > 0 ? getrs(n, a, n, pivots.data(), x) : 0;
  if (info != 0) throw std::runtime_error("LAPACK could not solve with the Jacobian (getrs status " + std::to_string(info) + ")");
}

template class CondensedLU<double>;
template class CondensedLU<std::complex<double>>;
template class NewtonLU<double>;
template class NewtonLU<std::complex<double>>;
} // namespace flextrack::multibody
