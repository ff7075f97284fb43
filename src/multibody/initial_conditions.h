// Consistent initial conditions for the GGL DAE, and redundant joint equations.
//
//  1. Positions: Gauss-Newton on Phi(q, t0) = 0 with the minimum-norm, mass-weighted correction
//       dx = -M^-1 B^T (B M^-1 B^T)^+ Phi      (dx in velocity coordinates, q += T(q) dx)
//     The pseudo-inverse (SVD, singular values below 1e-10 of the largest dropped) copes with
//     redundant equations before they are known.
//  2. Redundancy, at the projected configuration (multibody/redundancy.h): a joint equation
//     that depends on the earlier ones (Gram-Schmidt on the scaled rows of B, in joint order) at
//     the start *and* at assembled configurations nearby is dropped (its joint and equation are
//     reported; its reaction is then not unique). One that depends on the others at the start
//     only marks a singular configuration (a dead point, links in line): an InputError naming
//     the joints. Dependent equations that cannot be satisfied (conflicting joints) show up as a
//     position residual that the projection cannot remove: also an InputError naming the joints.
//  3. Velocities: v = v0 - M^-1 B^T (B M^-1 B^T)^-1 (B v0 + Phi_t), active equations only.
//  4. Accelerations and multipliers from the index-1 system
//       [M B^T; B 0] [v'; lambda] = [Q; gamma],  gamma = -d/dt (B v + Phi_t) at fixed v
//     (gamma by a central difference in time along q' = T v, step 1e-6 s); q' = T v; mu = 0.
//  With static_equilibrium, between 2 and 3: the positions are moved to the static equilibrium
//  at t0 and the velocities set to zero (multibody/static_equilibrium.h); step 3 then gives the
//  velocities that the drivers prescribe at t0 (zero for drivers at rest).
#pragma once

#include <multibody/redundancy.h>
#include <multibody/static_equilibrium.h>
#include <multibody/system.h>

#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace flextrack::multibody
{
struct InitialConditionSettings
{
  double tolerance = 1e-11;       ///< max |Phi| [m or -] after projection
  unsigned int max_iterations = 50;
  double rank_tolerance = 1e-8;   ///< relative remainder below which a row is dependent
  bool static_equilibrium = false; ///< start from the static equilibrium (Multibody/Initial state)
  EquilibriumSettings equilibrium;
};

struct BodyCorrection
{
  std::string body;
  double displacement = 0;   ///< |Delta R| [m]
  double rotation = 0;       ///< angle of the orientation change [rad]
  double modal = 0;          ///< |Delta eta| [modal units]
  double velocity = 0;       ///< |Delta v| (all velocity coordinates of the body, mixed units)
};

struct InitialConditionReport
{
  std::vector<BodyCorrection> corrections;
  std::vector<DroppedEquation> dropped;
  unsigned int iterations = 0;
  unsigned int neighbours_checked = 0; ///< configurations nearby where the redundancy was confirmed
  double neighbour_distance = 0;       ///< their distance from the start [m] (in the scene's length scale)
  double position_residual = 0, velocity_residual = 0; ///< every joint equation, dropped ones included
  EquilibriumReport equilibrium; ///< solved = false unless asked for
  std::string text() const; ///< several lines for a log
};

/// Builds consistent (y, yp) at @p t0 from the bodies' initial states and drops the redundant
/// joint equations of @p system (call once, after System::finalize()).
InitialConditionReport consistent_initial_conditions(System &system, double t0, dealii::Vector<double> &y,
                                                     dealii::Vector<double> &yp,
                                                     const InitialConditionSettings &settings = {});

/// The velocities of y moved onto the active joint equations B v + Phi_t = 0 and onto the
/// @p prescribed values (index in y of a velocity, value), by the change of least kinetic-energy
/// norm: the velocity jump of an impulse through the joints (an impact at an end stop).
void project_velocities(const System &system, double t, dealii::Vector<double> &y,
                        const std::vector<std::pair<unsigned int, double>> &prescribed);

/// Accelerations and multipliers at (t, y) from the index-1 system; fills yp (q', v') and the
/// lambda part of y; mu = 0. Coordinates held at end stops keep v' = 0.
void consistent_derivatives(System &system, double t, dealii::Vector<double> &y, dealii::Vector<double> &yp);
} // namespace flextrack::multibody
