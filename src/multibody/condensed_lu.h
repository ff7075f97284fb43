// Dense LU of the DAE's Newton matrix with its leading unknowns (the positions q) condensed out
// first, where their diagonal block splits into small independent blocks.
//
// Why: in the Newton matrix G = dF/dy + cj dF/dy' of a time step, the kinematic rows
// q' - T(q) v + Phi_q^T mu + 2 p mu_p = 0 give the q-q block cj I - d(T v)/dq + 2 mu_p I, which
// is block diagonal - a body's frame (R, p), each modal or track coordinate alone - once the
// Newton matrix leaves out d(Phi_q^T mu)/dq (System::use_newton_matrix). With Q the leading
// unknowns and R the rest (velocities, multipliers):
//   C = G_QQ^{-1} G_QR (block by block),  S = G_RR - G_RQ C (over C's nonzeros),  LU of S,
// and a solve is y_Q = G_QQ^{-1} b_Q, x_R = S^{-1} (b_R - G_RQ y_Q), x_Q = y_Q - C x_R. The LU
// then works on the velocities and multipliers only: the laser robot's 170 unknowns become 104.
//
// Where the block does not split so (a joint whose markers sit on one body, derivatives taken by
// differences; a static solve with cj = 0, whose q-q block is singular), or a block's pivot is
// poor, factorize() says so, leaves the matrix as it was, and the caller factorises it whole
// (NewtonLU below).
//
// Number is double (IDA's and generalised-alpha's Newton matrix, Radau IIA's real one) or
// std::complex<double> (Radau IIA's complex Newton matrix J + (alpha - i beta) / h M).
#pragma once

#include <vector>

namespace flextrack::multibody
{
enum class CondensedResult
{
  factored,
  singular,      ///< the complement has an exactly zero pivot: the matrix is singular
  not_applicable ///< the leading block does not split into small, well-pivoted blocks
};

template <typename Number>
class CondensedLU
{
public:
  using Result = CondensedResult;
  /// The largest block of leading unknowns eliminated as one (a body's R and p are 7).
  static constexpr unsigned int max_block = 8;

  /// Factorises the dense column-major n x n matrix @p a in place (C over G_QR, S's LU factors over
  /// G_RR), eliminating its first @p n_leading unknowns. Unchanged unless the result is factored.
  Result factorize(Number *a, unsigned int n, unsigned int n_leading);
  /// x = A^{-1} x with the factors in @p a, after factorize() returned factored.
  void solve(const Number *a, Number *x) const;
  /// The unknowns left in the dense complement (after factorize()).
  unsigned int complement_size() const { return n - n_lead; }

private:
  unsigned int n = 0, n_lead = 0;
  /// The leading blocks: their unknowns, and their LU factors (row major, k x k) with row swaps.
  std::vector<unsigned int> block_start, block_members, block_factor_start;
  std::vector<Number> block_factors;
  std::vector<int> block_pivots;
  std::vector<int> complement_pivots; ///< S's row swaps (LAPACK)

  /// x_Q = G_QQ^{-1} x_Q, the leading entries of each column of the n x @p columns array @p x.
  void solve_blocks(Number *x, unsigned int columns, unsigned int ld) const;
};

/// The dense LU of a Newton matrix as the integrators use it: condensed where CondensedLU
/// applies, LAPACK's LU of the whole matrix (getrf) otherwise. One place for that choice, for
/// JacobianSolver's dense path and Radau IIA's real and complex matrices.
template <typename Number>
class NewtonLU
{
public:
  /// Factorises the column-major n x n matrix @p a in place, the first @p n_condensed unknowns
  /// condensed out where their blocks allow (0: never); false if the matrix is singular.
  bool factorize(Number *a, unsigned int n, unsigned int n_condensed);
  /// x = A^{-1} x with the factors in @p a, after factorize() returned true.
  void solve(const Number *a, Number *x) const;
  /// Whether the last factorisation condensed, and the unknowns its LU then worked on.
  bool condensed() const { return used_condensed; }
  unsigned int complement_size() const { return condensed_lu.complement_size(); }

private:
  unsigned int n = 0;
  bool used_condensed = false;
  CondensedLU<Number> condensed_lu;
  std::vector<int> pivots; ///< getrf's row swaps of the whole matrix
};
} // namespace flextrack::multibody
