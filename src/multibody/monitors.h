// Monitors of a run: constraint residuals (of every joint equation, the dropped redundant ones
// included), Euler-parameter drift, GGL multiplier size, and the energy balance
//   E(t) - E(0) = W_applied + W_drivers - D
// with E = kinetic + gravity potential + strain energy (1/2 eta^T K eta) + spring potential,
// W_applied the work of applied loads, W_drivers the work of the constraint forces
// (int lambda^T Phi_t dt: only rheonomic equations, the drivers, contribute), D the dissipated
// energy (modal damping eta'^T D eta', dampers). The powers are integrated as a quadrature over
// every internal IDA step: Simpson's rule on IDA's interpolating polynomial (step start, middle,
// end), so the quadrature error is O(h^5) per step, below the integrator's own error. An output
// row inside a step (IDA steps past it and interpolates back) gets the works up to its own time:
// the sum over the finished steps minus the part of the last step after the row, that part from
// the quadratic through the step's three powers (no new evaluation; O(h^4) per row, not summed).
// Geometric stiffening is a linearised, non-conservative force (no potential is kept for it):
// the balance closes exactly only without it.
#pragma once

#include <array>
#include <limits>

#include <multibody/time_integrator.h>
#include <multibody/system.h>

#include <deal.II/lac/vector.h>

namespace flextrack::multibody
{
struct MonitorValues
{
  double time = 0;                 ///< [s]
  double position_residual = 0;    ///< max |Phi| over every joint equation, dropped ones included [m or -]
  double velocity_residual = 0;    ///< max |B v + Phi_t| over every joint equation [m/s or 1/s]
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
  /// Integrates the powers over every internal step of @p integrator (sets its step hook);
  /// @p integrator must outlive the calls to evaluate().
  void attach(TimeIntegrator &integrator);
  Powers powers(double t, const dealii::Vector<double> &y) const;
  /// Everything at (t, y), with the works accumulated up to t (t inside IDA's last step, where
  /// output rows are interpolated, or at its end).
  MonitorValues evaluate(double t, const dealii::Vector<double> &y) const;

private:
  /// Works [J] over the integrator's last step [t0, t1] (Simpson on its interpolating
  /// polynomial); keeps the three powers for partial_step_work().
  Powers step_work(double t0, double t1) const;
  /// Works [J] from the start of the last step to t inside it, from the powers step_work() kept.
  Powers partial_step_work(double t) const;

  const System &system;
  const TimeIntegrator *ida = nullptr;
  double work_applied = 0, work_drivers = 0, dissipated = 0; ///< up to the end of the last step
  double step_begin = 0, step_end = 0;                       ///< IDA's last step [s]
  Powers step_total;                                         ///< the works over that step [J]
  /// The powers at the end of the last step: the next step starts there (unless the state was
  /// reset, e.g. at an impact), so Simpson's rule needs two new evaluations per step, not three.
  mutable double last_time = std::numeric_limits<double>::quiet_NaN();
  mutable dealii::Vector<double> last_state;
  mutable Powers last_powers;
  mutable std::array<Powers, 3> step_powers; ///< at the last step's start, middle and end [W]
};

/// The energy balance error of a run, E(t) - E(0) - (W_applied + W_drivers - D), relative to the
/// run's energy scale so far: the largest |kinetic|, |gravity|, |strain| and |spring| energy and
/// |work| seen at the rows up to now. Relative to the energy at the row itself it exploded where
/// a pendulum turns (0.547 for a balance that closed to 1.8e-4 of the run's energies, issue 25,
/// item 12).
class EnergyBalance
{
public:
  explicit EnergyBalance(const MonitorValues &start) : start(start) {}
  /// The relative balance error at @p now (a row after the previous ones).
  double error(const MonitorValues &now);
  /// The largest |balance| of the rows so far relative to the energy scale of all of them: the
  /// run's figure. The largest row-wise error is not: at the first rows of a run that starts at
  /// rest every energy is round-off, and the scale so far is round-off too (the slewing beam's
  /// first row, 1e-18 J, gave 1.31 for a balance that closes to 2.3e-3 over the run).
  double largest_relative_to_run_scale() const { return largest_balance / scale; }

private:
  MonitorValues start;
  double scale = 1e-300;       ///< [J]
  double largest_balance = 0;  ///< [J]
};
} // namespace flextrack::multibody
