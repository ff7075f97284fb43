// Static equilibrium of a multibody scene (issue 9 item 8): the configuration in which the
// scene rests under gravity and the loads at the start time, so that a sagged arm does not
// start with a jolt.
//
// Unknowns: the position coordinates of every body and joint (frames R, p; modal coordinates
// eta; joints' own coordinates), as displacements dx in velocity coordinates (q += T(q) dx, the
// Euler parameters renormalised), and the multipliers lambda of the active joint equations.
// Velocities are zero; drivers and applied loads are held at their values at t0. Equations
// (the equations of motion with v = v' = 0, and the position constraints):
//   r_f = B(q)^T lambda - Q(q, v = 0, t0) = 0      (n_v: forces [N], torques [N m], modal forces)
//   r_c = Phi(q, t0)                       = 0      (active joint equations [m or -])
// solved by a damped Newton iteration on
//   [K_T  B^T] [dx     ]     [r_f]
//   [B    0  ] [dlambda] = - [r_c],      K_T = d r_f / dx (from the DAE Jacobian:
//                                          multibody/static_stiffness.h),
// with a backtracking line search on the scaled residual norm (steps halved until it
// decreases) and every step limited to 0.5 rad of rotation. The matrix is equilibrated (rows and
// columns by their largest entries) and factorised by SVD.
//
// A singular matrix (smallest singular value below 1e-10 of the largest) is not yet a mechanism.
// A pendulum started horizontal has one: the first multipliers (least squares of B^T lambda =
// Q) carry no force along the link there, so nothing turns with the body and K_T has no
// stiffness on the swing, although the load on it is unbalanced (issue 25, item 3: a double
// pendulum was refused as "a mechanism"). So:
//  - singular and the residual balanced (to the tolerances below) along every singular direction
//    (the left singular vectors): a motion that no joint, driver, spring or load stiffness holds,
//    and nothing pushes along it either: a slider on a level guide, a free body. Refused naming
//    the coordinate that moves most along it. The same when the matrix is singular at the
//    equilibrium found;
//  - singular and unbalanced, or no Newton step that decreases the residual: a step of the
//    mass-shifted tangent, K_T + mu M in the matrix above (M the mass matrix: a Levenberg-
//    Marquardt step in the kinetic-energy metric, or one implicit step of the motion with strong
//    damping), mu at least twice the most negative eigenvalue of K_T on the constraint null space
//    against M (so the shifted stiffness holds every allowed motion and the step goes downhill,
//    towards a stable equilibrium) and at least the unbalanced acceleration over 0.25 rad or
//    0.25 of the scene's size (the first step turns a body by about that much); the step is
//    limited to 0.5 rad and 0.5 of the scene's size and taken without the residual test (going
//    downhill from a stationary point the unbalanced load first grows), and the multipliers are
//    then those of least squares at the new positions. From the first such step on, Newton steps
//    are taken only where the stiffness on the allowed motions is positive (no Newton step up to
//    a maximum or a saddle), so the iteration ends at a stable equilibrium.
// An iteration that does not reach the tolerance is refused naming the worst residual component.
//
// Converged when max |r_f| <= relative_tolerance * (largest load component at the start, or 1
// if there is no load) and max |Phi| <= position_tolerance. Newton goes to the equilibrium
// nearest the given state where it has a step: a pendulum given at 150 degrees finds the
// inverted equilibrium, one given horizontal hangs (the shifted steps go down); an inclined
// slider that nothing holds slides on until max_iterations and is refused. Stability: the
// equilibrium found is linearised (multibody/linearization.h, as `flextrack linearize` does) and
// judged by classify_stability(): unstable if a mode grows, with its growth rate [1/s].
// (Before, the sign of the smallest eigenvalue of K_T on the constraint null space was compared
// with -1e-8 x the largest row sum of K_T, a bound in mixed units: a flexible body's stiff
// modes (up to (2 pi 32 kHz)^2 = 4e10 per modal mass) made it -920 and hid the -10.6 of
// gravity of a flexible link balanced upside down, called stable while it grows at 5.2 1/s.)
#pragma once

#include <multibody/system.h>

#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace flextrack::multibody
{
struct EquilibriumSettings
{
  double relative_tolerance = 1e-10;  ///< of max |r_f| against the largest load component [-]
  double position_tolerance = 1e-11;  ///< max |Phi| [m or -]
  unsigned int max_iterations = 100;
  double singular_tolerance = 1e-10;  ///< of the equilibrated matrix's singular values [-]
};

/// How far one body moved from the given state to the equilibrium.
struct EquilibriumMove
{
  std::string body;
  double displacement = 0; ///< |Delta R| of the frame origin [m]
  double rotation = 0;     ///< angle of the orientation change [rad]
  double modal = 0;        ///< |Delta eta| [modal units]
};

struct EquilibriumReport
{
  bool solved = false;           ///< false: not asked for
  unsigned int iterations = 0;   ///< Newton iterations
  unsigned int shifted_steps = 0; ///< of those, steps with the mass-shifted tangent K_T + mu M
  double force_residual = 0;     ///< max |B^T lambda - Q| at the end [N, N m, modal forces]
  double load_scale = 0;         ///< the largest load component at the start (the reference of the tolerance)
  double position_residual = 0;  ///< max |Phi| at the end [m or -]
  bool stable = true;            ///< no mode of the linearisation about it grows (classify_stability)
  unsigned int unstable_modes = 0; ///< modes that grow
  double growth_rate = 0;        ///< largest Re s of those [1/s]; 0 when stable
  std::vector<EquilibriumMove> moves;
  std::string text() const;      ///< lines for a log
};

/// Moves the positions of @p y (sized System::size(), active equations only) to the static
/// equilibrium at @p t0 and sets the velocities to zero (lambda is left for the caller to
/// recompute; the stability analysis recomputes it on a copy). InputError with the entry "Multibody/Initial state" when there is none (not
/// converged) or it is not unique (singular: a mechanism under these loads).
EquilibriumReport solve_static_equilibrium(System &system, double t0, dealii::Vector<double> &y,
                                           const EquilibriumSettings &settings = {});
} // namespace flextrack::multibody
