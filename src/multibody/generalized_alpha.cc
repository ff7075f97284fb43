// Generalised-alpha on the system's DAE (generalized_alpha.h).
#include <multibody/generalized_alpha.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <iomanip>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
constexpr double newton_tolerance = 0.33; ///< weighted norm of the correction, as IDA's test
constexpr double divergence_rate = 0.9;   ///< a Newton rate above this is a failure
constexpr double smallest_step = 1e-12;   ///< [s]
} // namespace

std::array<double, 3> GeneralizedAlphaIntegrator::parameters(const double rho)
{
  const double alpha_f = rho / (1 + rho), gamma = 1 / (1 + rho);
  return {{0.5 + alpha_f - gamma, alpha_f, gamma}};
}

GeneralizedAlphaIntegrator::GeneralizedAlphaIntegrator(System &s, const IntegratorSettings &settings_)
  : system(s), settings(settings_)
{
  const auto p = parameters(settings.spectral_radius);
  alpha_m = p[0], alpha_f = p[1], gamma = p[2];
  // The error constant C of the principal root, R(mu) = exp(mu) + C mu^3 + O(mu^4), from the
  // amplification matrix of y' = lambda y at mu = h lambda = 1e-2. Unknowns (y1, h w1):
  //   (1 - alpha_m) W1 - (1 - alpha_f) mu y1 = alpha_f mu y0 - alpha_m W0,  y1 - gamma W1 = y0 + (1 - gamma) W0.
  const double mu = 1e-2;
  const double a11 = -(1 - alpha_f) * mu, a12 = 1 - alpha_m, a21 = 1, a22 = -gamma;
  const double b11 = alpha_f * mu, b12 = -alpha_m, b21 = 1, b22 = 1 - gamma;
  const double det = a11 * a22 - a12 * a21;
  const double m11 = (a22 * b11 - a12 * b21) / det, m12 = (a22 * b12 - a12 * b22) / det,
               m21 = (-a21 * b11 + a11 * b21) / det, m22 = (-a21 * b12 + a11 * b22) / det;
  const double tr = m11 + m22, dt = m11 * m22 - m12 * m21, disc = std::sqrt(std::max(0.0, tr * tr / 4 - dt));
  const double principal = std::abs(tr / 2 + disc - std::exp(mu)) < std::abs(tr / 2 - disc - std::exp(mu)) ? tr / 2 + disc
                                                                                                          : tr / 2 - disc;
  error_constant = std::abs(principal - std::exp(mu)) / (mu * mu * mu);
}

void GeneralizedAlphaIntegrator::initialize(const double t0, const State &y0, const State &yp0)
{
  system.use_newton_matrix(true); // Newton without d(Phi_q^T mu)/dq (System)
  system.differential_components(differential);
  absolute.reinit(system.size());
  for (unsigned int i = 0; i < system.size(); ++i)
    absolute[i] = i < system.n_q()                   ? settings.absolute_tolerance
                  : i < system.n_q() + system.n_v() ? settings.velocity_tolerance_of(i - system.n_q())
                                                     : settings.multiplier_tolerance;
  t_now = t_last = t0;
  y = y_last = y0;
  yp = yp_last = yp0;
  w = yp0; // Arnold & Bruls: w_0 = y'(t0)
  h_before = 0;
  h_next = settings.step;
  matrix_c = -1;
  stats = IntegratorStatistics();
  output_origin = t0;
}

void GeneralizedAlphaIntegrator::reinitialize(const double t, const State &y0, const State &yp0)
{
  // A one-step method: the state is all it needs (w restarts at y', as at the start).
  t_now = t_last = t;
  y = y_last = y0;
  yp = yp_last = yp0;
  w = yp0;
  h_before = 0;
  h_next = settings.step;
  matrix_c = -1;
}

double GeneralizedAlphaIntegrator::weighted_norm(const State &d, const State &at) const
{
  double sum = 0;
  for (unsigned int i = 0; i < d.size(); ++i)
    {
      const double e = d[i] / (settings.relative_tolerance * std::abs(at[i]) + absolute[i]);
      sum += e * e;
    }
  return std::sqrt(sum / std::max<std::size_t>(1, d.size()));
}

bool GeneralizedAlphaIntegrator::attempt_step(const double h)
{
  const double t1 = t_now + h;
  const double c = (1 - alpha_m) / (h * gamma * (1 - alpha_f));
  const unsigned int n = system.size();
  State F(n), dy(n);
  for (int attempt = 0; attempt < 2; ++attempt)
    {
      // Predictor: y' constant; y from the update formulas (algebraic unknowns: unchanged).
      y_new.reinit(n), yp_new.reinit(n), w_new.reinit(n);
      for (unsigned int i = 0; i < n; ++i)
        if (differential[i] != 0)
          {
            yp_new[i] = yp[i];
            w_new[i] = ((1 - alpha_f) * yp_new[i] + alpha_f * yp[i] - alpha_m * w[i]) / (1 - alpha_m);
            y_new[i] = y[i] + h * ((1 - gamma) * w[i] + gamma * w_new[i]);
          }
        else
          y_new[i] = y[i];
      if (!(std::abs(c - matrix_c) <= 1e-8 * c)) // a new step size: the old matrix is not worth keeping
        {
          system.assemble_jacobian(t1, c, y_new, yp_new);
          ++stats.jacobian_evaluations;
          ++stats.factorizations;
          matrix_c = std::numeric_limits<double>::quiet_NaN(); // no usable factors until this one succeeds
          if (!system.factorize()) return false;
          stats.condensed_factorizations = system.n_condensed_factorizations();
          stats.condensed_unknowns = system.condensed_size();
          matrix_c = c;
          matrix_fresh = true;
        }
      double previous = 0;
      for (unsigned int k = 0; k < settings.max_newton_iterations; ++k)
        {
          system.residual(t1, y_new, yp_new, F);
          ++stats.residual_evaluations;
          ++stats.nonlinear_iterations;
          bool finite = true;
          for (unsigned int i = 0; i < n; ++i) finite = finite && std::isfinite(F[i]);
          if (!finite) break;
          system.solve(F.data(), dy.data());
          for (unsigned int i = 0; i < n; ++i)
            {
              y_new[i] -= dy[i];
              if (differential[i] != 0) yp_new[i] -= c * dy[i];
            }
          const double norm = weighted_norm(dy, y_new);
          if (!std::isfinite(norm)) break;
          const double rate = k == 0 ? 0.0 : norm / previous;
          if (k > 0 && rate > divergence_rate) break;
          // Converged when the last correction is small in the tolerances' norm. (IDA's test,
          // rate / (1 - rate) |correction| <= 0.33, accepted corrections of 100 here: the
          // first rate, from a far predictor, says nothing of the modified Newton's later one.)
          if (norm <= newton_tolerance)
            {
              for (unsigned int i = 0; i < n; ++i)
                if (differential[i] != 0)
                  w_new[i] = ((1 - alpha_f) * yp_new[i] + alpha_f * yp[i] - alpha_m * w[i]) / (1 - alpha_m);
                else
                  yp_new[i] = (y_new[i] - y[i]) / h, w_new[i] = yp_new[i];
              matrix_fresh = false;
              return true;
            }
          previous = norm;
        }
      if (matrix_fresh) // a fresh matrix did not help: the step is too large
        {
          ++stats.nonlinear_convergence_failures;
          return false;
        }
      ++stats.newton_restarts;
      matrix_c = -1; // retry once with a matrix at this step
    }
  return false;
}

double GeneralizedAlphaIntegrator::local_error(const double h) const
{
  if (h_before <= 0) return 0; // the first step: no history for the third difference
  // y''' ~ 2 / (h + h_before) ((y'_new - y') / h - (y' - y'_before) / h_before); error ~ C h^3 y'''.
  State e(y.size());
  for (unsigned int i = 0; i < e.size(); ++i)
    if (differential[i] != 0)
      {
        const double third = 2 / (h + h_before) * ((yp_new[i] - yp[i]) / h - (yp[i] - yp_before[i]) / h_before);
        e[i] = error_constant * h * h * h * third;
      }
  return weighted_norm(e, y_new);
}

double GeneralizedAlphaIntegrator::integrate(const double t_end, const double output_interval, const Observer &output)
{
  start_roots(t_now, y, yp);
  const double t_first = t_now;
  double next_output = next_output_time(t_now, output_interval, t_end);
  const double tiny = 1e-12 * std::max(1.0, std::abs(t_end));
  long steps_here = 0;
  while (t_now < t_end - tiny)
    {
      // Fixed steps end at t_first + k step exactly (no drift of a running sum), so output times
      // that are multiples of the step fall on step ends.
      double h = settings.adaptive_step ? h_next : t_first + double(steps_here + 1) * settings.step - t_now;
      if (settings.max_step > 0) h = std::min(h, settings.max_step);
      if (t_now + h >= t_end - tiny) // land on t_end
        h = t_end - t_now;
      else if (settings.adaptive_step && t_now + 1.5 * h > t_end) // and leave no sliver of a step
        h = 0.5 * (t_end - t_now);
      if (++steps_here > settings.max_steps)
        fail("more than 'Maximum steps' = " + std::to_string(settings.max_steps) + " steps", h,
             "raise 'Maximum steps' or shorten the run");
      // Attempt, shrinking on failure (adaptive) or failing (fixed step)
      for (;;)
        {
          // A residual that cannot be evaluated at the trial state (a contact pushed beyond its
          // track's overrun by a too large step) is a failed attempt, as IDA takes it: smaller
          // steps (adaptive), or a solver failure that says why (fixed step).
          bool converged = false;
          try
            {
              converged = attempt_step(h);
              last_problem.clear();
            }
          catch (const std::exception &e)
            {
              last_problem = e.what();
              ++stats.nonlinear_convergence_failures;
              matrix_c = -1;
            }
          if (converged)
            {
              if (!settings.adaptive_step) break;
              const double err = local_error(h);
              const double factor = std::clamp(0.9 * std::pow(std::max(err, 1e-10), -1.0 / 3), 0.2, 2.0);
              if (err <= 1)
                {
                  h_next = h * factor;
                  break;
                }
              ++stats.error_test_failures;
              h *= std::max(factor, 0.2);
            }
          else if (!settings.adaptive_step)
            fail(last_problem.empty() ? "Newton did not converge with a fresh matrix"
                                      : "the equations cannot be evaluated at the step's end: " + last_problem,
                 h);
          else
            h *= 0.25;
          if (h < smallest_step) fail("the step fell below 1e-12 s", h);
        }
      // Accept
      t_last = t_now;
      y_last = y, yp_last = yp;
      yp_before = yp, h_before = h;
      t_now += h;
      y = y_new, yp = yp_new, w = w_new;
      ++stats.steps;
      stats.last_step = h;
      if (finish_step(t_last, t_now, y, yp, t_end, output_interval, next_output, output)) return t_now;
    }
  return t_now;
}

void GeneralizedAlphaIntegrator::interpolate(const double t, State &yo, State &ypo) const
{
  const double h = t_now - t_last;
  yo.reinit(y.size()), ypo.reinit(y.size());
  if (h <= 0)
    {
      yo = y, ypo = yp;
      return;
    }
  const double s = std::clamp((t - t_last) / h, 0.0, 1.0);
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s, h01 = -2 * s * s * s + 3 * s * s,
               h11 = s * s * s - s * s;
  const double d00 = (6 * s * s - 6 * s) / h, d10 = 3 * s * s - 4 * s + 1, d01 = (-6 * s * s + 6 * s) / h, d11 = 3 * s * s - 2 * s;
  for (unsigned int i = 0; i < y.size(); ++i)
    if (differential[i] != 0)
      {
        yo[i] = h00 * y_last[i] + h10 * h * yp_last[i] + h01 * y[i] + h11 * h * yp[i];
        ypo[i] = d00 * y_last[i] + d10 * yp_last[i] + d01 * y[i] + d11 * yp[i];
      }
    else
      {
        yo[i] = (1 - s) * y_last[i] + s * y[i];
        ypo[i] = (y[i] - y_last[i]) / h;
      }
}

void GeneralizedAlphaIntegrator::fail(const std::string &what, const double h, const std::string &advice) const
{
  State F;
  std::string largest;
  try
    {
      system.residual(t_now + h, y_new.size() ? y_new : y, yp_new.size() ? yp_new : yp, F);
      unsigned int worst = 0;
      for (unsigned int i = 0; i < F.size(); ++i)
        if (!(std::abs(F[i]) <= std::abs(F[worst]))) worst = i;
      std::ostringstream r;
      r << "Largest residual: " << system.component_name(worst) << " (" << F[worst] << ")";
      largest = r.str();
    }
  catch (const std::exception &e)
    {
      largest = std::string("The residual cannot be evaluated there (") + e.what() + ")";
    }
  std::ostringstream s;
  s << std::setprecision(6) << "the time integration (generalised-alpha, rho_inf " << settings.spectral_radius
    << ") failed at t = " << t_now << " s, step " << std::setprecision(3) << h << " s: " << what
    << ". " << largest << ". What to change: "
    << (!advice.empty()           ? advice
        : settings.adaptive_step ? "look for a singular configuration near that time, or loosen the tolerances"
                                 : "set a smaller 'Step', or 'Adaptive step' = true");
  throw SolverError(s.str());
}
} // namespace flextrack::multibody
