// The residual of static equilibrium and its tangent (used by static_equilibrium.cc).
//
// At rest (v = v' = 0) and multipliers lambda of the active joint equations:
//   r_f = B(q)^T lambda - Q(q, v = 0, t0)      (n_v rows: forces, torques, modal forces)
//   r_c = Phi(q, t0)                          (active joint equations)
// and the tangent K_T = d r_f / dx along the velocity coordinates (positions move by
// q += T(q) dx, System::move_positions). r_f is the velocity rows of the DAE residual at
// v = v' = 0, so K_T = (dF_v / dq) T(q): the DAE Jacobian's velocity rows and position columns
// (analytic for the bodies, joints and forces: System::assemble_jacobian) times T. That costs about as much as one Jacobian of the run, where
// differences of the whole residual over every velocity coordinate cost 2 n_v residuals (for
// the laser robot with its full FE bases, n_v = 1145: 228 s of start-up, 2026-12-02).
#pragma once

#include <multibody/system.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

namespace flextrack::multibody
{
/// (r_f, r_c) at the positions of @p y (its velocities are not read) and @p lambda.
void static_residual(const System &system, double t0, const dealii::Vector<double> &y,
                     const dealii::Vector<double> &lambda, dealii::Vector<double> &r);

/// The velocity rows of the DAE Jacobian at the state (@p y, @p yp), alpha = 0: the stiffness
/// K = (dF_v / dq) T(q) along the velocity coordinates and the damping C = dF_v / dv (each
/// n_v x n_v; @p C may be nullptr), where F_v = M(q) v' - Q(q, v, v', t) + B(q)^T lambda. Used by
/// the static tangent below and by linearize() (multibody/linearization.h). Assembles the
/// system's Jacobian (its matrix is overwritten).
void velocity_row_tangents(System &system, double t, const dealii::Vector<double> &y, const dealii::Vector<double> &yp,
                           dealii::FullMatrix<double> &K, dealii::FullMatrix<double> *C);

/// K_T (n_v x n_v) from the DAE Jacobian and B (active equations x n_v) at @p y, @p lambda.
/// Assembles the system's Jacobian (its matrix is overwritten).
void static_stiffness(System &system, double t0, const dealii::Vector<double> &y, const dealii::Vector<double> &lambda,
                      dealii::FullMatrix<double> &K, dealii::FullMatrix<double> &B);

/// The same K_T by central differences of r_f, step @p h along each velocity coordinate: the
/// test oracle of static_stiffness().
void static_stiffness_by_differences(const System &system, double t0, const dealii::Vector<double> &y,
                                     const dealii::Vector<double> &lambda, double h, dealii::FullMatrix<double> &K,
                                     dealii::FullMatrix<double> &B);
} // namespace flextrack::multibody
