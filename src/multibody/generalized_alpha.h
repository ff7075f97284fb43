// Generalised-alpha on the system's GGL DAE F(t, y, y') = 0 (system.h), the second integrator
// beside IDA (issue 11). The first-order form of the method (Jansen, Whiting & Hulbert 2000) in
// the formulation of Arnold & Bruls (2007): every equation, the constraints and the Euler
// parameters' normalisation among them, holds at t_{n+1}; the derivative y' is replaced in the
// update by a filtered variable w,
//   (1 - alpha_m) w_{n+1} + alpha_m w_n = (1 - alpha_f) y'_{n+1} + alpha_f y'_n,
//   y_{n+1} = y_n + h ((1 - gamma) w_n + gamma w_{n+1}),
// with alpha_f = rho / (1 + rho), gamma = 1 / (1 + rho), alpha_m = 1/2 + alpha_f - gamma: second
// order for every rho_inf = rho in [0, 1], and a mode far above 1 / h is multiplied by -rho per
// step (rho = 1: no numerical damping; rho = 0: annihilated). The algebraic unknowns (multipliers)
// are solved for directly. Newton on y'_{n+1} has the matrix dF/dy + c dF/dy' with
// c = (1 - alpha_m) / (h gamma (1 - alpha_f)): the same System::assemble_jacobian as IDA's.
// The matrix is kept over steps (modified Newton) until Newton converges slowly or c changes.
//
// Fixed step, or adaptive: the local error is estimated from the third divided difference of y'
// times the method's error constant, and the step follows it (doc/multibody.md).
#pragma once

#include <multibody/time_integrator.h>

namespace flextrack::multibody
{
class GeneralizedAlphaIntegrator : public OneStepIntegrator
{
public:
  GeneralizedAlphaIntegrator(System &system, const IntegratorSettings &settings);

  void initialize(double t0, const State &y, const State &yp) override;
  void reinitialize(double t, const State &y, const State &yp) override;
  double integrate(double t_end, double output_interval, const Observer &output) override;
  /// Cubic Hermite interpolation of y (and its derivative) over the last step; linear for the
  /// algebraic unknowns.
  void interpolate(double t, State &y, State &yp) const override;
  IntegratorStatistics statistics() const override { return stats; }
  double time() const override { return t_now; }

  /// The method's parameters for @p rho_inf: {alpha_m, alpha_f, gamma}.
  static std::array<double, 3> parameters(double rho_inf);

private:
  /// One step of size @p h from the current state into (y_new, yp_new, w_new); false if Newton
  /// did not converge even with a fresh matrix.
  bool attempt_step(double h);
  /// Weighted RMS norm of @p d with the weights of the state @p y (the tolerances).
  double weighted_norm(const State &d, const State &y) const;
  /// Local error estimate of the step just attempted, in the weighted norm (accept if <= 1).
  double local_error(double h) const;
  /// Throws SolverError: the time, the step, @p what happened, the largest residual and @p advice
  /// (empty: the advice for a Newton failure).
  [[noreturn]] void fail(const std::string &what, double h, const std::string &advice = "") const;

  System &system;
  IntegratorSettings settings;
  double alpha_m, alpha_f, gamma, error_constant;
  State differential; ///< 1 for unknowns with a derivative in F, 0 for algebraic ones
  State absolute;     ///< absolute tolerance per unknown

  double t_now = 0;
  State y, yp, w;                 ///< at t_now
  State y_new, yp_new, w_new;     ///< the step being attempted
  double t_last = 0;              ///< start of the last accepted step (interpolation)
  State y_last, yp_last;          ///< at t_last
  State yp_before;                ///< y' one step before t_last (error estimate)
  double h_before = 0;            ///< that step's size; 0: none yet
  double h_next = 0;
  double matrix_c = -1;           ///< c of the factorised matrix; < 0: none
  bool matrix_fresh = false;      ///< factorised at the current step's first iterate
  /// Why the last attempt could not evaluate the equations (a contact pushed off its track by a
  /// too large step), as IDA's recoverable residual failure; empty if it could.
  std::string last_problem;

  IntegratorStatistics stats;
};
} // namespace flextrack::multibody
