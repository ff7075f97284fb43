// Radau IIA of order 5 on the system's DAE (radau_iia.h).
#include <multibody/radau_iia.h>

#include <multibody/jacobian_solver.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
// Hairer & Wanner's RADAU5 defaults (Solving ODEs II, IV.8 and the code's documentation).
constexpr unsigned int max_newton_iterations = 7;
constexpr double safety = 0.9;
constexpr double largest_growth = 8, largest_shrink = 5; ///< of the step, per step
/// Keep the Jacobian for the next step when Newton contracted at least this fast. RADAU5 uses
/// 1e-3 for cheap Jacobians and advises 0.1 for costly ones: ours is two assemblies and two LUs.
constexpr double keep_jacobian_below = 0.1;
constexpr double smallest_step = 1e-12; ///< [s], or 16 eps |t| where that is larger
constexpr double eps = std::numeric_limits<double>::epsilon();

double det3(const double a[3][3])
{
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/// r = a^-1 for 3 x 3 arrays, by cofactors (the method's constants below were measured with it).
void invert3(const double a[3][3], double r[3][3])
{
  const double det = det3(a);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      {
        // cofactor of a[j][i] over det
        const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
        r[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
      }
}

RadauCoefficients derive()
{
  RadauCoefficients r;
  const double s6 = std::sqrt(6.0);
  r.c[0] = (4 - s6) / 10, r.c[1] = (4 + s6) / 10, r.c[2] = 1;
  const double A[3][3] = {{(88 - 7 * s6) / 360, (296 - 169 * s6) / 1800, (-2 + 3 * s6) / 225},
                          {(296 + 169 * s6) / 1800, (88 + 7 * s6) / 360, (-2 - 3 * s6) / 225},
                          {(16 - s6) / 36, (16 + s6) / 36, 1.0 / 9}};
  std::copy(&A[0][0], &A[0][0] + 9, &r.A[0][0]);
  invert3(A, r.A_inverse);
  const auto &B = r.A_inverse;
  // Eigenvalues of B: its characteristic polynomial x^3 - tr x^2 + m x - det has one real root
  // (Newton from 3.6) and a complex pair alpha +- i beta.
  const double tr = B[0][0] + B[1][1] + B[2][2];
  const double m = B[0][0] * B[1][1] - B[0][1] * B[1][0] + B[0][0] * B[2][2] - B[0][2] * B[2][0] + B[1][1] * B[2][2] -
                   B[1][2] * B[2][1];
  const double det = 1 / det3(A); // det B
  double x = 3.6;
  for (int it = 0; it < 50; ++it) x -= (((x - tr) * x + m) * x - det) / ((3 * x - 2 * tr) * x + m);
  r.gamma = x;
  r.alpha = (tr - x) / 2;
  r.beta = std::sqrt(det / x - r.alpha * r.alpha);
  // T = [real eigenvector, Re v, Im v] with v the eigenvector of alpha + i beta; each eigenvector
  // is the cross product of two rows of B - lambda I.
  using C = std::complex<double>;
  auto eigenvector = [&](const C lambda, C v[3]) {
    C row0[3], row1[3];
    for (int k = 0; k < 3; ++k)
      row0[k] = B[0][k] - (k == 0 ? lambda : 0.0), row1[k] = B[1][k] - (k == 1 ? lambda : 0.0);
    v[0] = row0[1] * row1[2] - row0[2] * row1[1];
    v[1] = row0[2] * row1[0] - row0[0] * row1[2];
    v[2] = row0[0] * row1[1] - row0[1] * row1[0];
  };
  C real_vector[3], complex_vector[3];
  eigenvector(r.gamma, real_vector);
  eigenvector(C(r.alpha, r.beta), complex_vector);
  for (int k = 0; k < 3; ++k)
    {
      r.T[k][0] = real_vector[k].real();
      r.T[k][1] = complex_vector[k].real();
      r.T[k][2] = complex_vector[k].imag();
    }
  invert3(r.T, r.T_inverse);
  // The embedded formula of order 3 (RADAU5): y^ = y + h (gamma_0 y'_0 + sum b^_i Y'_i) with
  // gamma_0 = 1 / gamma and b^ from the order conditions sum b^_i c_i^(k-1) = 1 / k - gamma_0 [k = 1].
  // Then y^ - y_{n+1} = gamma_0 h y'_0 + sum_j e_j Z_j, e_j = sum_i (b^_i - b_i) (A^-1)_ij, and the
  // estimate (J + gamma / h M)^-1 M (y'_0 + sum_j gamma e_j Z_j / h) (radau_iia.h).
  double V[3][3], V_inverse[3][3];
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i) V[k][i] = std::pow(r.c[i], k);
  invert3(V, V_inverse);
  const double rhs[3] = {1 - 1 / r.gamma, 0.5, 1.0 / 3};
  double b_hat[3];
  for (int i = 0; i < 3; ++i) b_hat[i] = V_inverse[i][0] * rhs[0] + V_inverse[i][1] * rhs[1] + V_inverse[i][2] * rhs[2];
  for (int j = 0; j < 3; ++j)
    {
      double e = 0;
      for (int i = 0; i < 3; ++i) e += (b_hat[i] - A[2][i]) * B[i][j];
      r.error_weights[j] = r.gamma * e;
    }
  return r;
}

} // namespace

const RadauCoefficients &RadauCoefficients::get()
{
  static const RadauCoefficients coefficients = derive();
  return coefficients;
}

RadauIntegrator::RadauIntegrator(System &s, const IntegratorSettings &settings_)
  : system(s), settings(settings_), rc(RadauCoefficients::get())
{}

void RadauIntegrator::initialize(const double t0, const State &y0, const State &yp0)
{
  n = system.size();
  system.use_newton_matrix(true); // simplified Newton: J without d(Phi_q^T mu)/dq (System)
  system.differential_components(differential);
  // The local error estimate is tested against the tolerances as given, as IDA's is. (RADAU5
  // loosens them to 0.1 rtol^(2/3): at rtol 1e-6 that is 1e-5, and the paths of the scenes of
  // prm/bench/default_*.prm were then 0.7e-4 to 4.3e-4 of their extent off instead of 0.2e-5 to
  // 1.6e-5; doc/benchmarks.md.)
  rtol = settings.relative_tolerance;
  atol.assign(n, -1);
  for (unsigned int i = 0; i < system.n_q(); ++i) atol[i] = settings.absolute_tolerance;
  for (unsigned int k = 0; k < system.n_v(); ++k) atol[system.n_q() + k] = settings.velocity_tolerance_of(k);
  weight.assign(n, 0);
  stats = IntegratorStatistics();
  stats.steps_limited_by.assign(n, 0);
  output_origin = t0;
  reinitialize(t0, y0, yp0);
}

void RadauIntegrator::reinitialize(const double t, const State &y0, const State &yp0)
{
  // A one-step method: the state is all it needs.
  t_now = t_last = t;
  y = y_last = y0;
  yp = yp0;
  h_last = 0;
  have_step = false;
  restart = true;
  have_jacobian = jacobian_fresh = false;
  factored_h = -1;
  convergence_factor = 1;
  h_next = settings.initial_step > 0 ? settings.initial_step : 1e-6; // RADAU5's first step
  if (settings.max_step > 0) h_next = std::min(h_next, settings.max_step);
  update_weights();
}

void RadauIntegrator::update_weights()
{
  for (unsigned int i = 0; i < n; ++i) weight[i] = atol[i] < 0 ? 0.0 : 1 / (rtol * std::abs(y[i]) + atol[i]);
}

double RadauIntegrator::weighted_norm(const double *d) const
{
  double sum = 0;
  unsigned int count = 0;
  for (unsigned int i = 0; i < n; ++i)
    if (weight[i] > 0)
      {
        const double e = d[i] * weight[i];
        sum += e * e;
        ++count;
      }
  return std::sqrt(sum / std::max(1u, count));
}

bool RadauIntegrator::evaluate_jacobian(const double t, const State &y0, const State &yp0)
{
  try
    {
      system.assemble_jacobian_parts(t, y0, yp0, M); // dF/dy into the system's matrix, dF/dy' into M
      copy_to_dense(system.jacobian(), J);
    }
  catch (const std::exception &)
    {
      return false;
    }
  ++stats.jacobian_evaluations;
  have_jacobian = jacobian_fresh = true;
  factored_h = -1;
  return true;
}

bool RadauIntegrator::factorize(const double h)
{
  E1.resize(J.size());
  E2.resize(J.size());
  const double g = rc.gamma / h;
  const std::complex<double> z(rc.alpha / h, -rc.beta / h);
  for (std::size_t k = 0; k < J.size(); ++k)
    {
      E1[k] = J[k] + g * M[k];
      E2[k] = J[k] + z * M[k];
    }
  ++stats.factorizations;
  factored_h = -1;
  // The positions condensed out first where their blocks are uncoupled (condensed_lu.h): the
  // q rows of E are gamma / h I - d(T v)/dq, as in IDA's Newton matrix.
  const unsigned int nq = system.n_q();
  if (!lu1.factorize(E1.data(), n, nq) || !lu2.factorize(E2.data(), n, nq)) return false;
  if (lu1.condensed() && lu2.condensed()) ++stats.condensed_factorizations, stats.condensed_unknowns = lu1.complement_size();
  factored_h = h;
  return true;
}

RadauIntegrator::Outcome RadauIntegrator::newton(const double h, std::vector<State> &Z, double &theta,
                                                  unsigned int &iterations)
{
  // Newton stops when its correction, in the tolerances' norm, is this small: RADAU5's
  // min(0.03, sqrt(rtol)), but not below 1e-3 (RADAU5 goes down to 1e-5 at rtol 1e-10, below the
  // round-off of a stiff flexible body's residual: the laser robot at rtol 1e-10 failed Newton
  // on 19 966 of 29 169 steps and took 61 s; with 1e-3, none and 10 s, its path unchanged to
  // 1e-11 m), nor below 10 eps / rtol.
  const double fnewt = std::max(10 * eps / rtol, std::min(0.03, std::max(1e-3, std::sqrt(rtol))));
  std::vector<State> F(3, State(n));
  State stage(n), stage_derivative(n), dW1(n), re(n), im(n);
  std::vector<std::complex<double>> dW23(n);
  convergence_factor = std::pow(std::max(convergence_factor, eps), 0.8);
  double previous = 0, rate_before = 0;
  theta = 0;
  // Held steps (hold_step) cannot be cut: they get more iterations and no early give-up.
  const unsigned int limit = held_step > 0 ? 3 * max_newton_iterations : max_newton_iterations;
  for (unsigned int k = 0; k < limit; ++k)
    {
      for (unsigned int i = 0; i < 3; ++i)
        {
          for (unsigned int l = 0; l < n; ++l)
            {
              stage[l] = y[l] + Z[i][l];
              stage_derivative[l] =
                (rc.A_inverse[i][0] * Z[0][l] + rc.A_inverse[i][1] * Z[1][l] + rc.A_inverse[i][2] * Z[2][l]) / h;
            }
          try
            {
              system.residual(t_now + rc.c[i] * h, stage, stage_derivative, F[i]);
            }
          catch (const std::exception &)
            {
              return Outcome::failed; // a contact pushed off its track by a too large step
            }
          ++stats.residual_evaluations;
          for (unsigned int l = 0; l < n; ++l)
            if (!std::isfinite(F[i][l])) return Outcome::failed;
        }
      ++stats.nonlinear_iterations;
      // The transformed right-hand sides -T^-1 F, solved block by block
      for (unsigned int l = 0; l < n; ++l)
        {
          const auto &Ti = rc.T_inverse;
          dW1[l] = -(Ti[0][0] * F[0][l] + Ti[0][1] * F[1][l] + Ti[0][2] * F[2][l]);
          dW23[l] = -std::complex<double>(Ti[1][0] * F[0][l] + Ti[1][1] * F[1][l] + Ti[1][2] * F[2][l],
                                          Ti[2][0] * F[0][l] + Ti[2][1] * F[1][l] + Ti[2][2] * F[2][l]);
        }
      lu1.solve(E1.data(), dW1.data());
      lu2.solve(E2.data(), dW23.data());
      for (unsigned int l = 0; l < n; ++l) re[l] = dW23[l].real(), im[l] = dW23[l].imag();
      const double a = weighted_norm(dW1.data()), b = weighted_norm(re.data()), c = weighted_norm(im.data());
      const double norm = std::sqrt((a * a + b * b + c * c) / 3);
      if (!std::isfinite(norm)) return Outcome::failed;
      if (k > 0)
        {
          const double rate = norm / previous;
          theta = k == 1 ? rate : std::sqrt(rate * rate_before);
          rate_before = rate;
          if (theta >= 0.99) return Outcome::diverged;
          convergence_factor = theta / (1 - theta);
          // Not converging within the iterations left: give up early (RADAU5)
          if (held_step == 0 &&
              convergence_factor * norm * std::pow(theta, double(max_newton_iterations - 1 - k)) / fnewt >= 1)
            return Outcome::diverged;
        }
      previous = std::max(norm, eps);
      const auto &T = rc.T;
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int l = 0; l < n; ++l) Z[i][l] += T[i][0] * dW1[l] + T[i][1] * re[l] + T[i][2] * im[l];
      if (convergence_factor * norm <= fnewt)
        {
          iterations = k + 1;
          return Outcome::converged;
        }
    }
  return Outcome::diverged;
}

double RadauIntegrator::local_error(const double h, const std::vector<State> &Z, const bool refine)
{
  State v(n), rhs(n), e(n);
  for (unsigned int l = 0; l < n; ++l)
    v[l] = yp[l] + (rc.error_weights[0] * Z[0][l] + rc.error_weights[1] * Z[1][l] + rc.error_weights[2] * Z[2][l]) / h;
  for (unsigned int l = 0; l < n; ++l)
    {
      double sum = 0;
      for (unsigned int k = 0; k < n; ++k)
        if (differential[k] != 0) sum += M[std::size_t(k) * n + l] * v[k];
      rhs[l] = sum;
    }
  e = rhs;
  lu1.solve(E1.data(), e.data());
  for (unsigned int l = 0; l < n; ++l)
    if (differential[l] == 0) e[l] = 0;
  double err = weighted_norm(e.data());
  if (err >= 1 && refine) // RADAU5: on the first step and after a rejection, once more through f(y + e)
    {
      State shifted(y), F0, F1;
      shifted += e;
      try
        {
          system.residual(t_now, y, yp, F0);
          system.residual(t_now, shifted, yp, F1);
          stats.residual_evaluations += 2;
          for (unsigned int l = 0; l < n; ++l) e[l] = rhs[l] - (F1[l] - F0[l]);
          lu1.solve(E1.data(), e.data());
          for (unsigned int l = 0; l < n; ++l)
            if (differential[l] == 0) e[l] = 0;
          err = weighted_norm(e.data());
        }
      catch (const std::exception &)
        {} // keep the first estimate
    }
  if (err <= 1)
    {
      unsigned int worst = 0;
      for (unsigned int l = 0; l < n; ++l)
        if (std::abs(e[l] * weight[l]) > std::abs(e[worst] * weight[worst])) worst = l;
      ++stats.steps_limited_by[worst];
    }
  return std::isfinite(err) ? std::max(err, 1e-10) : 1e10;
}

void RadauIntegrator::polynomial(const double t, State &yo, State *ypo) const
{
  // Lagrange basis on the nodes 0, c1, c2, 1 (the value at 0 is y_last, so its term is y_last)
  const double s = (t - t_last) / h_last;
  const double nodes[4] = {0, rc.c[0], rc.c[1], 1};
  double L[3], dL[3];
  for (int k = 1; k <= 3; ++k)
    {
      double value = 1, slope = 0;
      for (int m = 0; m < 4; ++m)
        if (m != k)
          {
            const double f = (s - nodes[m]) / (nodes[k] - nodes[m]);
            slope = slope * f + value / (nodes[k] - nodes[m]);
            value *= f;
          }
      L[k - 1] = value, dL[k - 1] = slope / h_last;
    }
  yo = y_last;
  for (unsigned int l = 0; l < y_last.size(); ++l) yo[l] += L[0] * Z_last[0][l] + L[1] * Z_last[1][l] + L[2] * Z_last[2][l];
  if (ypo)
    {
      ypo->reinit(y_last.size());
      for (unsigned int l = 0; l < y_last.size(); ++l)
        (*ypo)[l] = dL[0] * Z_last[0][l] + dL[1] * Z_last[1][l] + dL[2] * Z_last[2][l];
    }
}

void RadauIntegrator::interpolate(const double t, State &yo, State &ypo) const
{
  if (!have_step || h_last <= 0)
    {
      yo = y, ypo = yp;
      return;
    }
  polynomial(std::clamp(t, t_last, t_last + h_last), yo, &ypo);
}

double RadauIntegrator::integrate(const double t_end, const double output_interval, const Observer &output)
{
  start_roots(t_now, y, yp);
  double next_output = next_output_time(t_now, output_interval, t_end);
  const double tiny = 1e-12 * std::max(1.0, std::abs(t_end));
  long steps_here = 0;
  double h_accepted = 0, error_accepted = 0; // of the last accepted step (Gustafsson's control)
  std::vector<State> Z(3, State(n));
  State yo;
  while (t_now < t_end - tiny)
    {
      double h = held_step > 0 ? held_step : h_next;
      if (settings.max_step > 0) h = std::min(h, settings.max_step);
      if (t_now + h >= t_end - tiny) h = t_end - t_now; // land on t_end
      else if (t_now + 1.5 * h > t_end) h = 0.5 * (t_end - t_now); // and leave no sliver of a step
      if (++steps_here > settings.max_steps)
        fail("more than 'Maximum steps' = " + std::to_string(settings.max_steps) + " steps", h,
             "raise 'Maximum steps' or shorten the run");
      bool rejected = false;
      double theta = 0, err = 0;
      for (;;)
        {
          if (h < std::max(smallest_step, 16 * eps * std::abs(t_now)))
            fail("the step fell below 1e-12 s (or below what changes t in double precision)", h, "");
          if (!have_jacobian && !evaluate_jacobian(t_now, y, yp))
            fail("the Jacobian cannot be evaluated at the step's start", h, "");
          if (factored_h != h && !factorize(h))
            {
              if (jacobian_fresh && held_step > 0) fail("the Newton matrix is singular at the held step", h, "");
              if (jacobian_fresh) h *= 0.5;
              else have_jacobian = false; // an old Jacobian: take one at this state first
              continue;
            }
          // Newton's start: the last step's collocation polynomial, extrapolated
          if (have_step)
            for (unsigned int i = 0; i < 3; ++i)
              {
                polynomial(t_now + rc.c[i] * h, yo, nullptr);
                for (unsigned int l = 0; l < n; ++l) Z[i][l] = yo[l] - y[l];
              }
          else
            for (State &z : Z) z = 0;
          unsigned int iterations = 0;
          const Outcome outcome = newton(h, Z, theta, iterations);
          if (outcome != Outcome::converged && held_step > 0 && jacobian_fresh)
            fail("Newton did not converge at the held step", h, "hold a smaller step");
          if (outcome != Outcome::converged)
            {
              if (!jacobian_fresh)
                {
                  ++stats.newton_restarts; // retry with a Jacobian at this state
                  have_jacobian = false;
                }
              else
                {
                  ++stats.nonlinear_convergence_failures;
                  h *= 0.5;
                  rejected = true; // the next step does not grow beyond this one
                }
              continue;
            }
          if (held_step > 0) break; // every step accepted
          err = local_error(h, Z, restart || rejected);
          const double factor = std::min(safety, safety * (1 + 2 * max_newton_iterations) /
                                                   (iterations + 2 * max_newton_iterations));
          double quotient = std::clamp(std::pow(err, 0.25) / factor, 1 / largest_growth, largest_shrink);
          if (err < 1)
            {
              if (h_accepted > 0) // Gustafsson's predictive controller
                {
                  const double predicted = std::clamp(h_accepted / h * std::pow(err * err / error_accepted, 0.25) / safety,
                                                      1 / largest_growth, largest_shrink);
                  quotient = std::max(quotient, predicted);
                }
              h_accepted = h, error_accepted = std::max(1e-2, err);
              double h_new = h / quotient;
              if (rejected) h_new = std::min(h_new, h);
              h_next = h_new;
              break;
            }
          ++stats.error_test_failures;
          rejected = true;
          h = restart ? 0.1 * h : h / quotient;
          // An old Jacobian under which Newton converged fast is not why the error was large:
          // kept (RADAU5 takes a new one after every rejection; on a flexible pendulum whose first
          // mode decides the step that was a Jacobian per rejected step, a quarter of the steps).
          if (!jacobian_fresh && theta > keep_jacobian_below) have_jacobian = false;
        }
      // Accept
      t_last = t_now;
      h_last = h;
      y_last = y;
      Z_last = Z;
      have_step = true;
      t_now += h;
      for (unsigned int l = 0; l < n; ++l)
        {
          y[l] = y_last[l] + Z[2][l];
          yp[l] = (rc.A_inverse[2][0] * Z[0][l] + rc.A_inverse[2][1] * Z[1][l] + rc.A_inverse[2][2] * Z[2][l]) / h;
        }
      ++stats.steps;
      ++stats.order_histogram[5];
      restart = false;
      stats.last_step = h;
      update_weights();
      // The Jacobian is kept while Newton contracts fast, and the factors while the step would
      // grow by less than 20 % (RADAU5).
      jacobian_fresh = false;
      have_jacobian = theta <= keep_jacobian_below;
      if (have_jacobian && h_next >= h && h_next <= 1.2 * h) h_next = h;
      // Roots over the step, on the collocation polynomial; the step hook; the outputs
      const double t_step_end = t_now;
      const bool stopped = finish_step(t_last, t_now, y, yp, t_end, output_interval, next_output, output);
      update_weights(); // at the state reached (a root moves it back into the step)
      // A root moved the state back into the step: its y' is the polynomial's, not the
      // collocation's, so the next error estimate is refined as on a first step.
      if (t_now < t_step_end) restart = true;
      if (stopped) return t_now;
    }
  return t_now;
}

void RadauIntegrator::fail(const std::string &what, const double h, const std::string &advice) const
{
  std::ostringstream s;
  s << std::setprecision(6) << "the time integration (Radau IIA) failed at t = " << t_now << " s, step "
    << std::setprecision(3) << h << " s: " << what << ". What to change: "
    << (!advice.empty() ? advice
                        : "look for a singular configuration or a contact leaving its track near that time, or "
                          "run with 'Method = ida'");
  throw SolverError(s.str());
}
} // namespace flextrack::multibody
