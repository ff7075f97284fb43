// Time integration of the system's GGL DAE with SUNDIALS IDA (variable-order, variable-step
// BDF), through IDA's C API rather than deal.II's wrapper, for three things the wrapper hides:
// root finding (the end of a track, issue 10), the step statistics (steps, error-test failures,
// order histogram, residual and Jacobian evaluations) and a direct solver of our own.
//
// The linear solver is a SUNLinearSolver of type DIRECT on a placeholder SUNMatrix: IDA decides
// when the Jacobian is stale and calls our Jacobian function (System::assemble_jacobian at
// alpha = c_j), then our setup (KLU numeric factorisation), then our solves; IDA itself rescales
// solutions when c_j changed since the last setup. The algebraic unknowns (lambda, mu) are
// excluded from the error test (IDASetId + IDASetSuppressAlg) and, with 'Multiplier tolerance =
// auto', from the Newton test (error weights of our own, IdaCallbacks::error_weights).
#pragma once

#include <multibody/time_integrator.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <functional>
#include <memory>
#include <string>

namespace flextrack::multibody
{
class IdaIntegrator : public TimeIntegrator
{
public:
  IdaIntegrator(System &system, const IntegratorSettings &settings);
  ~IdaIntegrator();

  void initialize(double t0, const State &y, const State &yp) override;
  void set_root_functions(unsigned int n, RootFunction g) override;
  void set_step_hook(std::function<void(double t_begin, double t_end)> hook) override { step_hook = std::move(hook); }
  void reinitialize(double t, const State &y, const State &yp) override;
  double integrate(double t_end, double output_interval, const Observer &output) override;
  /// y and y' at @p t within the last step (IDA's interpolating polynomial).
  void interpolate(double t, State &y, State &yp) const override;
  void interpolate_state(double t, State &y) const override;
  const std::vector<int> &roots_found() const override { return roots; }
  IntegratorStatistics statistics() const override;
  double time() const override { return t_now; }

private:
  [[noreturn]] void fail(int flag) const;
  void count_step_limiter();
  struct Sundials; // SUNContext, vectors, IDA memory, solver objects
  std::unique_ptr<Sundials> sun;
  System &system;
  IntegratorSettings settings;
  RootFunction root_function;
  unsigned int n_roots = 0;
  std::vector<int> roots;
  std::function<void(double, double)> step_hook;
  std::array<long, 6> histogram{};
  std::vector<long> limited_by; ///< IntegratorStatistics::steps_limited_by
  /// IDA's counters before the last reinitialize() (IDAReInit sets them to zero).
  IntegratorStatistics before_restart;
  double t_now = 0;
  double smallest_step = 0; ///< IDA's hmin in integrate() [s]: 1e-12 of the run
  mutable std::string last_message;
  long newton_failures_at_setup = 0; ///< IDA's count at the last factorisation (IdaCallbacks::ls_setup)

  friend struct IdaCallbacks;
};
} // namespace flextrack::multibody
