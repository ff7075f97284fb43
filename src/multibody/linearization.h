// Linearisation of the constrained equations of motion about a state (static equilibrium or a
// steady motion), and its eigenvalues.
//
// With displacements x in velocity coordinates (q = q0 (+) x through T(q0), so the Euler
// parameters stay normalised) and the residual of the equations of motion
//   R(x, v) = M(q) v'0 - Q(q, v, t) + B(q)^T lambda0
// (v'0, lambda0 from the index-1 system at the state), the stiffness K = dR/dx, the damping
// C = dR/dv (the DAE Jacobian's velocity rows: multibody/static_stiffness.h) and M are projected
// onto the null space N of the active constraint Jacobian B (orthonormal, from the SVD of B: the
// motions the joints allow):
//   (N^T M N) x'' + (N^T C N) x' + (N^T K N) x = 0.
// Its eigenvalues s = -zeta w +- i w sqrt(1 - zeta^2) give the frequencies |Im s| / 2 pi and the
// damping ratios -Re s / |s|; Re s > 0 is an instability. N is taken constant (its derivative
// times the constraint reactions is in K through B(q)^T lambda0). Drivers hold their rows, so a
// driven joint has no motion in N. Each mode also carries its shape (the displacement part of the
// right eigenvector, mapped back to velocity coordinates: N z), so that a caller can tell e.g. a
// flapwise from a chordwise bending mode.
#pragma once

#include <multibody/system.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <complex>
#include <string>
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

/// Orthonormal basis (columns, n_v x n_f) of the null space of the active constraint Jacobian
/// @p B (rows x n_v): the right singular vectors of singular values <= 1e-10 of the largest;
/// the identity when there is no row.
dealii::FullMatrix<double> constraint_null_space(const dealii::FullMatrix<double> &B, unsigned int n_v);

/// The one stability verdict of `flextrack linearize` and of the static equilibrium of `run`
/// (issue 25, item 3). A mode grows if
///   Re s > max(1e-10 x the largest |s| of all modes (at least 1 1/s), 1e-9 |s|):
/// a zero eigenvalue (a neutral motion: a slider free along a level track) comes out of the
/// eigen solver as round-off of about 1e-11 of the largest |s|; judged against its own |s| it was
/// called UNSTABLE (Re s = 4e-6 among modes up to 1e5 1/s, issue 25, item 4).
struct StabilityVerdict
{
  unsigned int unstable_modes = 0;
  double largest_growth_rate = 0; ///< largest Re s of the modes that grow [1/s]; 0 when none does
  double round_off = 0;           ///< the first bound above [1/s]
  std::vector<bool> grows;        ///< per mode of the list classified
  bool stable() const { return unstable_modes == 0; }
};
StabilityVerdict classify_stability(const std::vector<LinearMode> &modes);

/// How far a state is from an equilibrium or a steady motion (issue 25, item 4): linearising
/// about a state with v' != 0 is allowed (the eigenvalues then describe the motion near that
/// instant), but it is said. The accelerations are weighted by the mass so that translations,
/// rotations and modal coordinates compare (sqrt(M_ii) |v'_i|, in sqrt(kg) m/s^2 for each kind),
/// and measured against the forces acting on the same rows (max over i of
/// max(|Q_i|, |(B^T lambda)_i|) / sqrt(M_ii), same unit): the ratio is the unbalanced part of the
/// largest force, independent of the units and of the scene's size. Coordinates without mass (a
/// joint's own coordinates) are left out.
struct EquilibriumCheck
{
  double imbalance = 0;           ///< max_i sqrt(M_ii) |v'_i| / the force scale above [-]
  unsigned int component = 0;     ///< index in y of the velocity coordinate of that maximum
  double acceleration = 0;        ///< its v'_i [m/s^2, rad/s^2 or modal units/s^2]
  std::string name;               ///< System::component_name of it
  std::string unit;               ///< "m/s^2", "rad/s^2" or "1/s^2 (modal)"
  /// An equilibrium or a steady motion: imbalance <= tolerance.
  ///
  /// The tolerance, 1e-6: the static-equilibrium solve leaves at most 1e-10 of the largest load
  /// unbalanced, a state written by hand to 7 or more significant digits about 1e-7. An imbalance
  /// e moves the equilibrium by about e of what the load deflects (a pendulum e rad off its
  /// rest angle), and the eigenvalues, which depend on the configuration to first order, differ
  /// from those of the equilibrium nearby by about e relative: up to 1e-6 that is below what is
  /// printed; above it (a pendulum at 30 degrees has e = 0.4) the state is not an equilibrium.
  static constexpr double tolerance = 1e-6;
  bool is_equilibrium() const { return imbalance <= tolerance; }
  std::string note() const;       ///< the sentence for the log and summary.json when it is not
};
/// @p y with consistent lambda and @p yp with the accelerations v' (consistent_derivatives()).
EquilibriumCheck check_equilibrium(const System &system, double t, const dealii::Vector<double> &y,
                                   const dealii::Vector<double> &yp);
} // namespace flextrack::multibody
