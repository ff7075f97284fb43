// Time integration of the system's GGL DAE with SUNDIALS IDA (variable-order, variable-step
// BDF), through IDA's C API rather than deal.II's wrapper, for three things the wrapper hides:
// root finding (the end of a track, issue 10), the step statistics (steps, error-test failures,
// order histogram, residual and Jacobian evaluations) and a direct solver of our own.
//
// The linear solver is a SUNLinearSolver of type DIRECT on a placeholder SUNMatrix: IDA decides
// when the Jacobian is stale and calls our Jacobian function (System::assemble_jacobian at
// alpha = c_j), then our setup (KLU numeric factorisation), then our solves; IDA itself rescales
// solutions when c_j changed since the last setup. The algebraic unknowns (lambda, mu) are
// excluded from the error test (IDASetId + IDASetSuppressAlg).
#pragma once

#include <multibody/system.h>
#include <base/solver_error.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <functional>
#include <memory>
#include <string>

namespace flextrack::multibody
{
// A failure of the time integration throws flextrack::SolverError (base/solver_error.h); what()
// gives the time, the worst component by name and what to change.

struct IntegratorSettings
{
  double relative_tolerance = 1e-6; ///< [-]
  double absolute_tolerance = 1e-8; ///< [units of q, and of v unless velocity_tolerance is set]
  /// Absolute tolerance of the velocities [m/s, rad/s, modal units/s]; 0: absolute_tolerance.
  /// A looser one lets IDA step over stiff elastic modes whose vibration is far below the
  /// position tolerance but whose velocity (omega times larger) is not below a tight one.
  double velocity_tolerance = 0;
  /// Absolute tolerance of the multipliers lambda, mu [N, N m, 1/s]. They are excluded from the
  /// error test, so this enters only IDA's Newton convergence test, where a tight value fails:
  /// index-2 multipliers carry roundoff amplified by c_j ~ 1/h (mu ~ eps |q| / h).
  double multiplier_tolerance = 1e-2;
  unsigned int max_order = 5;       ///< BDF order limit, 1..5
  unsigned int max_newton_iterations = 4; ///< per step, before a Jacobian rebuild or a smaller step
  double max_step = 0;              ///< [s], 0: no limit
  double initial_step = 0;          ///< [s], 0: IDA's choice
  long max_steps = 1000000;         ///< internal steps per call of integrate()

  static void declare_parameters(dealii::ParameterHandler &prm);
  void parse_parameters(dealii::ParameterHandler &prm);
};

struct IntegratorStatistics
{
  long steps = 0, error_test_failures = 0, nonlinear_iterations = 0, nonlinear_convergence_failures = 0;
  long residual_evaluations = 0, jacobian_evaluations = 0, factorizations = 0;
  std::array<long, 6> order_histogram{}; ///< steps taken at order 1..5 (index = order)
  double last_step = 0;                  ///< [s]
};

class IdaIntegrator
{
public:
  using State = dealii::Vector<double>;
  using Observer = std::function<void(double t, const State &y, const State &yp)>;
  /// g(t, y, yp) -> n values; IDA stops where one changes sign.
  using RootFunction = std::function<void(double t, const State &y, const State &yp, double *g)>;

  IdaIntegrator(System &system, const IntegratorSettings &settings);
  ~IdaIntegrator();

  /// Start at @p t0 from consistent @p y, @p yp (consistent_initial_conditions()).
  void initialize(double t0, const State &y, const State &yp);
  void set_root_functions(unsigned int n, RootFunction g);
  /// Called after every internal step with the step's start and end time; interpolate() is valid
  /// on that interval (for quadratures such as the work of forces).
  void set_step_hook(std::function<void(double t_begin, double t_end)> hook) { step_hook = std::move(hook); }

  /// Integrates to @p t_end, calling @p output at t0 + k @p output_interval (k >= 1) and at the
  /// end. Returns the time reached: t_end, or earlier where a root function changed sign.
  double integrate(double t_end, double output_interval, const Observer &output);
  /// y and y' at @p t within the last step (IDA's interpolating polynomial).
  void interpolate(double t, State &y, State &yp) const;
  /// Root functions that changed sign at the last stop (+1 / -1 direction, 0 none).
  const std::vector<int> &roots_found() const { return roots; }
  IntegratorStatistics statistics() const;
  double time() const { return t_now; }

private:
  [[noreturn]] void fail(int flag) const;
  struct Sundials; // SUNContext, vectors, IDA memory, solver objects
  std::unique_ptr<Sundials> sun;
  System &system;
  IntegratorSettings settings;
  RootFunction root_function;
  unsigned int n_roots = 0;
  std::vector<int> roots;
  std::function<void(double, double)> step_hook;
  std::array<long, 6> histogram{};
  double t_now = 0;
  mutable std::string last_message;

  friend struct IdaCallbacks;
};
} // namespace flextrack::multibody
