// Radau IIA of order 5 (three stages) on the system's GGL DAE F(t, y, y') = 0 (system.h), the
// third integrator beside IDA and generalised-alpha (issue 24, item 3). The method of Hairer &
// Wanner's RADAU5 (Solving ODEs II, section IV.8), written here for an implicit DAE:
//  - collocation at c = (4 - sqrt 6) / 10, (4 + sqrt 6) / 10, 1: the stage increments Z_i solve
//      F(t + c_i h, y + Z_i, (1 / h) sum_k (A^-1)_ik Z_k) = 0,  i = 1..3,
//    and y_{n+1} = y + Z_3. Order 5 in the positions and velocities, 3 in the multipliers
//    (index 2); L-stable: a mode far above 1 / h is damped out, not amplified (BDF 3-5 are not
//    stable for lightly damped modes they step over, so IDA is held at order 2 on flexible scenes);
//  - simplified Newton with the matrix I x J + (1 / h) A^-1 x M, J = dF/dy, M = dF/dy', both
//    kept over steps; A^-1 = T diag(gamma, [alpha beta; -beta alpha]) T^-1 splits it into one
//    real system (J + gamma / h M) and one complex one (J + (alpha - i beta) / h M), each factorised
//    by LAPACK's dense LU;
//  - the local error of an embedded order-3 formula, filtered by (J + gamma / h M)^-1 so that
//    stiff components do not reject steps, against the tolerances as given (radau_iia.cc says why
//    not RADAU5's transformed ones);
//  - step size by Gustafsson's predictive controller; the dense output is the collocation
//    polynomial (interpolate(), root finding, the next step's Newton start).
// The multipliers are in neither the error nor the Newton test (as IDA's 'Multiplier tolerance =
// auto'; time_integrator.h).
#pragma once

#include <multibody/condensed_lu.h>
#include <multibody/time_integrator.h>

#include <complex>
#include <vector>

namespace flextrack::multibody
{
/// The method's constants, derived from its Butcher matrix when first used (radau_iia.cc).
struct RadauCoefficients
{
  double c[3];          ///< collocation points in [0, 1]
  double A[3][3];       ///< Butcher matrix
  double A_inverse[3][3];
  double gamma, alpha, beta; ///< eigenvalues of A^-1: gamma, alpha +- i beta
  double T[3][3], T_inverse[3][3]; ///< T^-1 A^-1 T = [gamma 0 0; 0 alpha beta; 0 -beta alpha]
  double error_weights[3]; ///< d_i of the error estimate (J + gamma / h M)^-1 M (y' + sum d_i Z_i / h)
  static const RadauCoefficients &get();
};

class RadauIntegrator : public OneStepIntegrator
{
public:
  RadauIntegrator(System &system, const IntegratorSettings &settings);

  void initialize(double t0, const State &y, const State &yp) override;
  void reinitialize(double t, const State &y, const State &yp) override;
  double integrate(double t_end, double output_interval, const Observer &output) override;
  /// The collocation polynomial of the last step (cubic, through y and the three stages).
  void interpolate(double t, State &y, State &yp) const override;
  /// Steps of exactly @p h [s] from now on, every one accepted (no error test; a Newton failure
  /// is a solver failure): for convergence studies of the method itself. 0: adaptive again.
  void hold_step(const double h) { held_step = h; }
  IntegratorStatistics statistics() const override { return stats; }
  double time() const override { return t_now; }

private:
  enum class Outcome { converged, diverged, failed };
  /// J = dF/dy and M = dF/dy' at (t, y, yp), dense; false if the equations cannot be evaluated.
  bool evaluate_jacobian(double t, const State &y, const State &yp);
  /// LU of J + gamma / h M and of J + (alpha - i beta) / h M; false if one is singular.
  bool factorize(double h);
  /// The stage equations for the step of size @p h from the current state, from the start Z;
  /// sets theta (Newton's contraction rate) and the iterations taken.
  Outcome newton(double h, std::vector<State> &Z, double &theta, unsigned int &iterations);
  /// The weighted local error estimate of the step just solved (accept if <= 1).
  double local_error(double h, const std::vector<State> &Z, bool refine);
  /// The collocation polynomial of the last accepted step at @p t (extrapolated outside it).
  void polynomial(double t, State &y, State *yp) const;
  /// 1 / (rtol' |y_i| + atol'_i) at the current state, 0 for untested components.
  void update_weights();
  double weighted_norm(const double *d) const;
  [[noreturn]] void fail(const std::string &what, double h, const std::string &advice) const;

  System &system;
  IntegratorSettings settings;
  const RadauCoefficients &rc;
  unsigned int n = 0;
  State differential;          ///< 1 for unknowns with a derivative in F
  double rtol = 0;             ///< relative tolerance [-]
  std::vector<double> atol;    ///< absolute tolerance per unknown; < 0: not tested
  std::vector<double> weight;  ///< error weights at the current state

  double t_now = 0;
  State y, yp;
  // The last accepted step, for the dense output: start time, size, start value and stages.
  double t_last = 0, h_last = 0;
  State y_last;
  std::vector<State> Z_last;
  bool have_step = false;
  /// The next step is the first after initialize(), reinitialize() or a root: its error estimate
  /// is refined, and a rejection cuts it by 10 (RADAU5's first step).
  bool restart = true;

  // Newton's matrices and their LU factors in place (column major), the positions condensed out
  // where they allow (condensed_lu.h).
  std::vector<double> J, M, E1;
  std::vector<std::complex<double>> E2;
  NewtonLU<double> lu1;
  NewtonLU<std::complex<double>> lu2;
  bool have_jacobian = false;  ///< J, M usable (kept over steps while Newton contracts fast)
  bool jacobian_fresh = false; ///< J, M taken at the current step's start
  double factored_h = -1;        ///< h of E1, E2; < 0: none
  double h_next = 0, convergence_factor = 1;
  double held_step = 0; ///< hold_step(); 0: adaptive

  IntegratorStatistics stats;
};
} // namespace flextrack::multibody
