// Monitors of a run: constraint residuals, Euler-parameter drift, GGL multiplier size, and the
// energy balance
//   E(t) - E(0) = W_applied + W_drivers - D
// with E = kinetic + gravity potential + strain energy (1/2 eta^T K eta) + spring potential,
// W_applied the work of applied loads, W_drivers the work of the constraint forces
// (int lambda^T Phi_t dt: only rheonomic equations, the drivers, contribute), D the dissipated
// energy (modal damping eta'^T D eta', dampers). The powers are integrated as a quadrature over
// every internal IDA step: Simpson's rule on IDA's interpolating polynomial (step start, middle,
// end), so the quadrature error is O(h^5) per step, below the integrator's own error.
// Geometric stiffening is a linearised, non-conservative force (no potential is kept for it):
// the balance closes exactly only without it.
#pragma once

#include <multibody/ida_integrator.h>
#include <multibody/system.h>

#include <deal.II/lac/vector.h>

namespace flextrack::multibody
{
struct MonitorValues
{
  double time = 0;                 ///< [s]
  double position_residual = 0;    ///< max |Phi| over the active joint equations [m or -]
  double velocity_residual = 0;    ///< max |B v + Phi_t| [m/s or 1/s]
  double normalisation_drift = 0;  ///< max ||p| - 1| [-]
  double max_mu = 0;               ///< max |mu|: zero on the exact solution
  double kinetic = 0, gravity = 0, strain = 0, springs = 0;        ///< [J]
  double work_applied = 0, work_drivers = 0, dissipated = 0;       ///< [J], since the start
  double energy() const { return kinetic + gravity + strain + springs; }
};

/// Powers [W] at one state: of applied loads, of constraint forces (drivers), dissipated.
struct Powers
{
  double applied = 0, drivers = 0, dissipation = 0;
};

class Monitors
{
public:
  explicit Monitors(const System &system) : system(system) {}
  /// Integrates the powers over every internal step of @p ida (sets its step hook).
  void attach(IdaIntegrator &ida);
  Powers powers(double t, const dealii::Vector<double> &y) const;
  /// Everything at (t, y), with the works accumulated so far.
  MonitorValues evaluate(double t, const dealii::Vector<double> &y) const;
  /// E(t) - E(0) - (W_applied + W_drivers - D), relative to max(|E(0)|, works): the balance error.
  static double balance_error(const MonitorValues &start, const MonitorValues &now);

private:
  const System &system;
  double work_applied = 0, work_drivers = 0, dissipated = 0;
};
} // namespace flextrack::multibody
