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
//   [B    0  ] [dlambda] = - [r_c],      K_T = d r_f / dx (central differences, h = 1e-6),
// with a backtracking line search on the scaled residual norm (steps halved until it
// decreases) and every step limited to 0.5 rad of rotation. The matrix is equilibrated (rows and
// columns by their largest entries) and factorised by SVD: a smallest singular value below
// 1e-10 of the largest means the scene is a mechanism under these loads (a motion that no
// joint, driver, spring or load stiffness holds: a slider on a level guide, a free body); that
// is refused naming the coordinate that moves most along the singular direction. An iteration
// that does not reach the tolerance is refused naming the worst residual component.
//
// Converged when max |r_f| <= relative_tolerance * (largest load component at the start, or 1
// if there is no load) and max |Phi| <= position_tolerance. The equilibrium found is the one
// Newton reaches from the given state: it may be unstable (an inverted pendulum); the report
// says so when the stiffness on the constraint null space has a negative eigenvalue.
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
  unsigned int max_iterations = 50;
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
  double force_residual = 0;     ///< max |B^T lambda - Q| at the end [N, N m, modal forces]
  double load_scale = 0;         ///< the largest load component at the start (the reference of the tolerance)
  double position_residual = 0;  ///< max |Phi| at the end [m or -]
  bool stable = true;            ///< the stiffness on the constraint null space is positive semi-definite
  double smallest_stiffness = 0; ///< its smallest eigenvalue (mixed units)
  std::vector<EquilibriumMove> moves;
  std::string text() const;      ///< lines for a log
};

/// Moves the positions of @p y (sized System::size(), active equations only) to the static
/// equilibrium at @p t0 and sets the velocities to zero (lambda is left for the caller to
/// recompute). InputError with the entry "Multibody/Initial state" when there is none (not
/// converged) or it is not unique (singular: a mechanism under these loads).
EquilibriumReport solve_static_equilibrium(const System &system, double t0, dealii::Vector<double> &y,
                                           const EquilibriumSettings &settings = {});
} // namespace flextrack::multibody
