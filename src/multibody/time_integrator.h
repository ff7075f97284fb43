// What every time integrator of the system's DAE offers (IDA's BDF, generalised-alpha), their
// settings (section Multibody/Integrator of a scene) and their statistics. The run command, the
// monitors and the tests see only this interface; make_integrator() picks the method.
#pragma once

#include <multibody/system.h>
#include <base/solver_error.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::multibody
{
// A failure of the time integration throws flextrack::SolverError (base/solver_error.h); what()
// gives the time, the worst component by name and what to change.

enum class IntegrationMethod { ida, generalized_alpha, radau };

struct IntegratorSettings
{
  IntegrationMethod method = IntegrationMethod::ida;
  /// "Method = auto" (the parameter's default): chosen by choose_automatic_settings() (Radau IIA
  /// for a scene with elastic modes, IDA otherwise). False here, so that settings built in code
  /// get the method they set.
  bool automatic_method = false;
  double relative_tolerance = 1e-6; ///< [-]
  double absolute_tolerance = 1e-8; ///< [units of q, and of v unless velocity_tolerance is set]
  /// Absolute tolerance of the velocities [m/s, rad/s, modal units/s]; 0: absolute_tolerance.
  /// A looser one lets IDA step over stiff elastic modes whose vibration is far below the
  /// position tolerance but whose velocity (omega times larger) is not below a tight one.
  double velocity_tolerance = 0;
  /// "Velocity tolerance = auto" (the default): chosen per velocity by choose_automatic_settings().
  bool automatic_velocity_tolerance = true;
  /// Per velocity coordinate (n_v), set by choose_automatic_settings(); empty: velocity_tolerance.
  std::vector<double> velocity_tolerances;
  /// "Maximum order = auto" (the default): chosen by choose_automatic_settings().
  bool automatic_max_order = true;
  /// The absolute tolerance of velocity coordinate @p k (index in v) [m/s, rad/s, modal units/s].
  double velocity_tolerance_of(std::size_t k) const
  {
    if (k < velocity_tolerances.size()) return velocity_tolerances[k];
    return velocity_tolerance > 0 ? velocity_tolerance : absolute_tolerance;
  }
  /// Absolute tolerance of the multipliers lambda, mu [N, N m, 1/s] when set to a number. They
  /// are excluded from the error test, so this enters only the Newton convergence test, where a
  /// tight value fails: index-2 multipliers carry roundoff amplified by c_j ~ 1/h (mu ~ eps |q| / h).
  double multiplier_tolerance = 1e-2;
  /// "Multiplier tolerance = auto" (the default): IDA leaves the joints' multipliers out of its
  /// Newton test, which bounds them through the velocities they move, and tests the bodies'
  /// normalisation multipliers against 1e-2 (ida_integrator.cc, error_weights);
  /// generalised-alpha uses 1e-2.
  bool automatic_multiplier_tolerance = true;
  unsigned int max_order = 5;       ///< BDF order limit, 1..5
  unsigned int max_newton_iterations = 4; ///< per step, before a Jacobian rebuild or a smaller step
  double max_step = 0;              ///< [s], 0: no limit
  double initial_step = 0;          ///< [s], 0: IDA's choice
  long max_steps = 1000000;         ///< internal steps per call of integrate()
  // Generalised-alpha only
  double step = 1e-3;               ///< [s] the fixed step, or the first one of an adaptive run
  bool adaptive_step = false;       ///< step size from a local error estimate and the tolerances
  double spectral_radius = 0.8;     ///< rho_inf [-], 0 (most damping of high frequencies) to 1 (none)

  static void declare_parameters(dealii::ParameterHandler &prm);
  void parse_parameters(dealii::ParameterHandler &prm);
  std::string method_name() const;
};

struct IntegratorStatistics
{
  long steps = 0, error_test_failures = 0, nonlinear_iterations = 0;
  /// Steps rejected because Newton did not converge with a Jacobian of that step (the step is cut).
  long nonlinear_convergence_failures = 0;
  /// Newton iterations that did not converge with a Jacobian of an earlier step, so the Jacobian
  /// was rebuilt and the same step solved again: a cost of modified Newton, not a rejected step.
  long newton_restarts = 0;
  long residual_evaluations = 0, jacobian_evaluations = 0, factorizations = 0;
  /// Factorisations with the positions condensed out (condensed_lu.h), and the unknowns left in
  /// their LU (of the last one).
  long condensed_factorizations = 0;
  unsigned int condensed_unknowns = 0;
  std::array<long, 6> order_histogram{}; ///< steps taken at order 1..5 (index = order)
  double last_step = 0;                  ///< [s]
  /// Per unknown, the steps at which it had the largest weighted local error (IDA: the unknown
  /// that limits the step size); empty where the integrator does not estimate it per unknown.
  std::vector<long> steps_limited_by;
};

class TimeIntegrator
{
public:
  using State = dealii::Vector<double>;
  using Observer = std::function<void(double t, const State &y, const State &yp)>;
  /// g(t, y, yp) -> n values; the integration stops where one changes sign.
  using RootFunction = std::function<void(double t, const State &y, const State &yp, double *g)>;

  virtual ~TimeIntegrator() = default;
  /// Start at @p t0 from consistent @p y, @p yp (consistent_initial_conditions()).
  virtual void initialize(double t0, const State &y, const State &yp) = 0;
  /// Restarts at @p t from consistent @p y, @p yp after a jump of the state (an impact at a track's
  /// end stop, a contact held or released there): the step history is dropped, the settings, root
  /// functions, statistics and output times (still t0 + k dt of initialize()) are kept.
  virtual void reinitialize(double t, const State &y, const State &yp) = 0;
  virtual void set_root_functions(unsigned int n, RootFunction g) = 0;
  /// Called after every internal step with the step's start and end time; interpolate() is valid
  /// on that interval (for quadratures such as the work of forces).
  virtual void set_step_hook(std::function<void(double t_begin, double t_end)> hook) = 0;
  /// Integrates to @p t_end, calling @p output at t0 + k @p output_interval (t0 of initialize(),
  /// the times after the current one) and at the end. Returns the time reached: t_end, or earlier
  /// where a root function changed sign (the state there is output too); calling it again goes on.
  virtual double integrate(double t_end, double output_interval, const Observer &output) = 0;
  /// y and y' at @p t within the last step.
  virtual void interpolate(double t, State &y, State &yp) const = 0;
  /// y alone at @p t within the last step (the monitors' quadrature of powers needs no y').
  virtual void interpolate_state(double t, State &y) const
  {
    State yp;
    interpolate(t, y, yp);
  }
  /// Root functions that changed sign at the last stop (+1 / -1 direction, 0 none).
  virtual const std::vector<int> &roots_found() const = 0;
  virtual IntegratorStatistics statistics() const = 0;
  virtual double time() const = 0;

protected:
  /// The first output time t0 + k dt after @p t_now (t0: output_origin), k >= 1.
  double next_output_time(double t_now, double output_interval, double t_end) const;
  double output_origin = 0; ///< t0 of initialize() [s]
};

/// What the one-step methods (generalised-alpha, Radau IIA) share: root functions located on
/// their own interpolant, the step hook and the outputs, after each accepted step.
class OneStepIntegrator : public TimeIntegrator
{
public:
  void set_root_functions(unsigned int n, RootFunction g) override;
  void set_step_hook(std::function<void(double t_begin, double t_end)> hook) override { step_hook = std::move(hook); }
  const std::vector<int> &roots_found() const override { return roots; }

protected:
  /// At the start of integrate(): no root found yet; the root functions' values at (t, y, yp).
  void start_roots(double t, const State &y, const State &yp);
  /// After the step from @p t_begin to @p t_now (interpolate() valid on it): the root functions
  /// that change sign over it are located by bisection on interpolate() and (t_now, y, yp) moved
  /// back to the earliest; then the step hook and the outputs due up to t_now (at most to
  /// @p t_end). Returns true if a root ends the integration (its state is output too).
  bool finish_step(double t_begin, double &t_now, State &y, State &yp, double t_end, double output_interval,
                   double &next_output, const Observer &output);

private:
  RootFunction root_function;
  unsigned int n_roots = 0;
  std::vector<int> roots;
  std::vector<double> g_old, g_new;
  std::function<void(double, double)> step_hook;
};

/// The entries left "auto" in @p settings, chosen for @p system (the method, velocity tolerances
/// per coordinate, the BDF order limit; doc/multibody.md, "Integrator defaults"), and the sentence that
/// says what was chosen and why (empty if nothing was automatic). Idempotent.
std::string choose_automatic_settings(const System &system, IntegratorSettings &settings);

/// The integrator that @p settings ask for, on @p system (entries left "auto" chosen first).
std::unique_ptr<TimeIntegrator> make_integrator(System &system, const IntegratorSettings &settings);
} // namespace flextrack::multibody
