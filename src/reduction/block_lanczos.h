// Block Lanczos for the largest eigenvalues of a symmetric operator known by its action on
// blocks of vectors, with full reorthogonalisation and no restart.
//
// Why a block method: in the standard form of the shift-invert eigen problem of a large body
// (modal_solver.cc), every application of the operator is two triangular solves with the
// Cholesky factor, and a triangular solve is bound by reading the factor from memory (0.6 GiB
// for a 1e5-dof hex20 body). Solved for b vectors at once, the factor is read once for all of
// them (CHOLMOD's supernodal solve turns into matrix-matrix products), so b vectors cost little
// more than one. ARPACK's single-vector Lanczos read the factor 2 x 63 times for 20 modes of the
// 1e5-dof link; this one, in blocks of 8, 2 x 17 times (doc/benchmarks.md).
//
// The method (Golub & Underwood's block Lanczos; Saad, "Numerical methods for large eigenvalue
// problems", 2nd ed., section 6.5): V_0 is an orthonormal n x b block; step j applies the
// operator, W = A V_j, orthogonalises W against every earlier block twice (classical Gram-
// Schmidt, twice is enough in floating point), and orthonormalises what is left into V_{j+1}.
// The projection H = V^T A V of the basis is read from the first orthogonalisation's
// coefficients, so it is the Rayleigh quotient of the basis itself, however the basis was
// orthogonalised. Its eigenpairs (theta, s) give Ritz pairs (theta, V s); the residual of one is
// || V_{j+1}^T A V_j s_j || (s_j: the last b entries of s), with no product by A. A pair is
// converged when that residual is at most tol |theta|, ARPACK's test.
//
// Columns that vanish in the orthogonalisation (the Krylov space became invariant) are replaced
// by fresh vectors, orthogonal to the basis: the projection stays exact, and the iteration goes
// on in the rest of the space. A repeated eigenvalue is found with its whole eigenspace only if
// its multiplicity is at most b (the block spans at most b directions of it; more come only
// from round-off): callers choose b above the multiplicities they expect (a free body's six
// rigid-body modes).
//
// The start block is the operator applied to smooth vectors, so that it lies in the operator's
// range: Ritz vectors of non-zero eigenvalues then have no component in its null space (for
// the shift-invert operator of a body, the supported dofs) beyond round-off.
#pragma once

#include <deal.II/lac/lapack_templates.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <numeric>
#include <optional>
#include <vector>

namespace flextrack::reduction
{
/// out = A in, for @p k vectors of the operator's size stored one after the other.
using BlockOperator = std::function<void(const double *in, double *out, unsigned int k)>;

struct BlockEigenpairs
{
  std::vector<double> values;  ///< the wanted eigenvalues, largest first
  std::vector<double> vectors; ///< their orthonormal eigenvectors, one after the other
  unsigned int block_steps = 0;    ///< applications of the operator to a block
  unsigned int basis_size = 0;     ///< columns of the Krylov basis at the end
};

namespace block_lanczos_detail
{
using dealii::types::blas_int;

/// C (rows x cols, leading dimension ldc) = alpha op(A) op(B) + beta C, column-major.
inline void gemm(const char ta, const char tb, const std::size_t rows, const std::size_t cols,
                 const std::size_t inner, const double alpha, const double *A, const std::size_t lda,
                 const double *B, const std::size_t ldb, const double beta, double *C, const std::size_t ldc)
{
  if (rows == 0 || cols == 0) return;
  if (inner == 0) // no product: C = beta C (BLAS would reject a leading dimension of 0)
    {
      for (std::size_t c = 0; c < cols; ++c)
        for (std::size_t r = 0; r < rows; ++r) C[c * ldc + r] = beta == 0 ? 0.0 : beta * C[c * ldc + r];
      return;
    }
  const blas_int m = rows, n = cols, k = inner, la = std::max<std::size_t>(lda, 1), lb = std::max<std::size_t>(ldb, 1),
                 lc = std::max<std::size_t>(ldc, 1);
  dealii::gemm(&ta, &tb, &m, &n, &k, &alpha, A, &la, B, &lb, &beta, C, &lc);
}

/// A start or replacement vector: smooth in the index, different for every @p seed.
inline void fill_start(double *v, const std::size_t n, const unsigned int seed)
{
  const double a = 0.37 + 0.113 * seed, phase = 0.71 * seed;
  for (std::size_t i = 0; i < n; ++i) v[i] = 1.0 + 0.1 * std::sin(a * static_cast<double>(i) + phase) + 0.01 * std::cos(0.05 * i * (seed + 1));
}

/// W -= V (V^T W) for the @p k columns of W and the first @p m columns of V (n rows);
/// @p C (m x k) receives V^T W.
inline void project_out(const double *V, const std::size_t n, const std::size_t m, double *W, const unsigned int k,
                        double *C)
{
  gemm('T', 'N', m, k, n, 1.0, V, n, W, n, 0.0, C, m);
  gemm('N', 'N', n, k, m, -1.0, V, n, C, m, 1.0, W, n);
}

/// Column @p c of W less its components along W's columns 0 .. c-1 (orthonormal already).
inline void project_out_earlier_columns(double *W, const std::size_t n, const unsigned int c)
{
  double *w = W + c * n;
  for (unsigned int d = 0; d < c; ++d)
    {
      const double *u = W + d * n;
      const double r = std::inner_product(u, u + n, w, 0.0);
      for (std::size_t i = 0; i < n; ++i) w[i] -= r * u[i];
    }
}

inline double norm(const double *w, const std::size_t n) { return std::sqrt(std::inner_product(w, w + n, w, 0.0)); }

/// Makes the @p k columns of W orthonormal and orthogonal to the first @p m columns of V (both
/// n rows): two passes of block classical Gram-Schmidt against V, each followed by modified
/// Gram-Schmidt inside W. A column that loses all but 1e-10 of its size is replaced by a fresh
/// vector (@p seed counts them). @p coefficients (m x k), if given, receives V^T W of the first pass.
inline void orthonormalise(const double *V, const std::size_t n, const std::size_t m, double *W, const unsigned int k,
                           double *coefficients, unsigned int &seed)
{
  std::vector<double> C(m * k), size_before(k);
  for (unsigned int c = 0; c < k; ++c) size_before[c] = norm(W + c * n, n);
  for (int pass = 0; pass < 2; ++pass)
    {
      project_out(V, n, m, W, k, C.data());
      if (pass == 0 && coefficients) std::copy(C.begin(), C.end(), coefficients);
      for (unsigned int c = 0; c < k; ++c)
        {
          double *w = W + c * n;
          project_out_earlier_columns(W, n, c);
          double size = norm(w, n);
          if (!(size > 1e-10 * size_before[c]))
            {
              // Deflated: a fresh direction, made orthogonal to V and to W's earlier columns.
              fill_start(w, n, ++seed);
              for (int again = 0; again < 2; ++again)
                {
                  project_out(V, n, m, w, 1, C.data());
                  project_out_earlier_columns(W, n, c);
                }
              size = norm(w, n);
            }
          for (std::size_t i = 0; i < n; ++i) w[i] /= size;
          size_before[c] = 1; // the second pass measures against the normalised column
        }
    }
}
} // namespace block_lanczos_detail

/// The @p n_wanted largest eigenpairs of the symmetric operator @p A of size @p n, with blocks of
/// @p block_size vectors, in a basis of at most @p max_basis columns; std::nullopt if they have
/// not converged to @p tolerance (relative residual) by then.
inline std::optional<BlockEigenpairs> block_lanczos(const BlockOperator &A, const std::size_t n,
                                                     const unsigned int n_wanted, const unsigned int block_size,
                                                     std::size_t max_basis, const double tolerance)
{
  using namespace block_lanczos_detail;
  const unsigned int b = block_size;
  // The basis and the block after it must fit in the space (n), or orthogonalising them fails.
  if (b == 0 || n_wanted == 0 || n < 2 * std::size_t(b)) return std::nullopt;
  max_basis = std::min(max_basis, n - b);
  if (max_basis < n_wanted + b) return std::nullopt;
  // Basis V (n x max_basis), projection H (max_basis x max_basis, upper triangle filled).
  std::vector<double> V(n * max_basis), H(max_basis * max_basis), W(n * b), AV(n * b), coupling(b * b);
  unsigned int seed = 0;
  for (unsigned int c = 0; c < b; ++c) fill_start(W.data() + c * n, n, seed++);
  A(W.data(), V.data(), b);
  orthonormalise(V.data(), n, 0, V.data(), b, nullptr, seed);
  BlockEigenpairs result;
  result.block_steps = 1;
  std::size_t m = b; // columns of V so far
  std::vector<double> S, theta;
  while (true)
    {
      // W = A V_j, j the last block; H's column block j = V^T W (rows 0..m).
      const std::size_t first = m - b;
      A(V.data() + first * n, AV.data(), b);
      ++result.block_steps;
      std::copy(AV.begin(), AV.end(), W.begin());
      std::vector<double> column(m * b);
      orthonormalise(V.data(), n, m, W.data(), b, column.data(), seed);
      for (unsigned int c = 0; c < b; ++c)
        for (std::size_t r = 0; r <= first + c; ++r) H[(first + c) * max_basis + r] = column[c * m + r];
      // The next block and its coupling V_{j+1}^T A V_j, which gives the Ritz residuals.
      gemm('T', 'N', b, b, n, 1.0, W.data(), n, AV.data(), n, 0.0, coupling.data(), b);
      // Rayleigh-Ritz in the m columns: eigenvalues ascending in theta, vectors in S.
      S.assign(m * m, 0.0);
      for (std::size_t c = 0; c < m; ++c)
        for (std::size_t r = 0; r <= c; ++r) S[c * m + r] = H[c * max_basis + r];
      theta.assign(m, 0.0);
      {
        const blas_int size = m, ld = m;
        blas_int lwork = -1, info = 0;
        double query = 0;
        dealii::syev("V", "U", &size, S.data(), &ld, theta.data(), &query, &lwork, &info);
        lwork = static_cast<blas_int>(query);
        std::vector<double> work(std::max<blas_int>(lwork, 1));
        dealii::syev("V", "U", &size, S.data(), &ld, theta.data(), work.data(), &lwork, &info);
        if (info != 0) return std::nullopt;
      }
      // The wanted pairs are the last n_wanted (largest theta).
      bool converged = m >= n_wanted + b;
      for (unsigned int w = 0; w < n_wanted && converged; ++w)
        {
          const std::size_t index = m - 1 - w;
          const double *s_last = S.data() + index * m + first;
          double residual = 0;
          for (unsigned int r = 0; r < b; ++r)
            {
              double entry = 0;
              for (unsigned int c = 0; c < b; ++c) entry += coupling[c * b + r] * s_last[c];
              residual += entry * entry;
            }
          converged = std::sqrt(residual) <= tolerance * std::abs(theta[index]);
        }
      if (!converged && m + b > max_basis) return std::nullopt;
      if (converged)
        {
          // Ritz vectors V S for the wanted pairs, largest first.
          std::vector<double> picked(m * n_wanted);
          for (unsigned int w = 0; w < n_wanted; ++w)
            {
              result.values.push_back(theta[m - 1 - w]);
              std::copy_n(S.data() + (m - 1 - w) * m, m, picked.data() + w * m);
            }
          result.vectors.assign(n * n_wanted, 0.0);
          gemm('N', 'N', n, n_wanted, m, 1.0, V.data(), n, picked.data(), m, 0.0, result.vectors.data(), n);
          result.basis_size = m;
          return result;
        }
      std::copy(W.begin(), W.end(), V.begin() + m * n);
      m += b;
    }
}
} // namespace flextrack::reduction
