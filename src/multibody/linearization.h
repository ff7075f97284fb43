// Linearisation of the constrained equations of motion about a state (static equilibrium or a
// steady motion), and its eigenvalues.
//
// With displacements x in velocity coordinates (q = q0 (+) x through T(q0), so the Euler
// parameters stay normalised) and the residual of the equations of motion
//   R(x, v) = M(q) v'0 - Q(q, v, t) + B(q)^T lambda0
// (v'0, lambda0 from the index-1 system at the state), the stiffness K = dR/dx, the damping
// C = dR/dv (central differences) and M are projected onto the null space N of the active
// constraint Jacobian B (orthonormal, from the SVD of B: the motions the joints allow):
//   (N^T M N) x'' + (N^T C N) x' + (N^T K N) x = 0.
// Its eigenvalues s = -zeta w +- i w sqrt(1 - zeta^2) give the frequencies |Im s| / 2 pi and the
// damping ratios -Re s / |s|; Re s > 0 is an instability. N is taken constant (its derivative
// times the constraint reactions is in K through B(q)^T lambda0). Drivers hold their rows, so a
// driven joint has no motion in N. Each mode also carries its shape (the displacement part of the
// right eigenvector, mapped back to velocity coordinates: N z), so that a caller can tell e.g. a
// flapwise from a chordwise bending mode.
#pragma once

#include <multibody/system.h>

#include <deal.II/lac/vector.h>

#include <complex>
#include <vector>

namespace flextrack::multibody
{
struct LinearMode
{
  std::complex<double> eigenvalue; ///< [1/s]
  double frequency_hz = 0;         ///< |Im s| / 2 pi
  double damping_ratio = 0;        ///< -Re s / |s|
  /// Displacement shape in velocity coordinates (n_v entries, complex, scaled to unit norm).
  std::vector<std::complex<double>> shape;
};

/// Modes of @p system linearised at (t, y) (y with consistent q, v; lambda is recomputed), sorted
/// by frequency, one entry per complex-conjugate pair (and every real eigenvalue).
std::vector<LinearMode> linearize(System &system, double t, const dealii::Vector<double> &y);
} // namespace flextrack::multibody
