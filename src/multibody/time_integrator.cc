// Integrator settings and the choice of method (time_integrator.h).
#include <base/input_error.h>
#include <base/text.h>
#include <multibody/generalized_alpha.h>
#include <multibody/ida_integrator.h>
#include <multibody/jacobian_solver.h>
#include <multibody/radau_iia.h>
#include <multibody/time_integrator.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

void IntegratorSettings::declare_parameters(ParameterHandler &prm)
{
  prm.declare_entry("Method", "auto", Patterns::Selection("auto|ida|radau|generalized_alpha"),
                    "auto (the default): radau when a flexible body has elastic modes, 'Maximum order' is "
                    "'auto' and the Jacobian is dense with at most 1000 unknowns, ida otherwise (the log says "
                    "which); ida: SUNDIALS IDA, variable-order "
                    "variable-step BDF (Gear's method); radau: Radau IIA of order 5 (three stages, L-stable, "
                    "as Hairer & Wanner's RADAU5), adaptive step, dense LU; generalized_alpha: second-order "
                    "generalised-alpha with numerical damping of high frequencies set by 'Spectral radius at "
                    "infinity', fixed or adaptive step (doc/multibody.md).");
  prm.declare_entry("Relative tolerance", "1e-6", Patterns::Double(0),
                    "Relative tolerance [-]: IDA's error test; generalised-alpha's Newton test and, with an "
                    "adaptive step, its error test.");
  prm.declare_entry("Absolute tolerance", "1e-8", Patterns::Double(0),
                    "Absolute tolerance, the same for every unknown [m, rad, modal units, and per s] (both methods).");
  prm.declare_entry("Velocity tolerance", "auto", Patterns::Anything(),
                    "IDA's absolute tolerance of the velocities [m/s, rad/s, modal units/s]: 'auto' (the "
                    "default), 0 (the absolute tolerance) or a number from 1e-15 to 1e6. 'auto': each modal "
                    "velocity gets the absolute tolerance times its mode's angular frequency, so a vibration "
                    "whose amplitude is within the position tolerance is not resolved in time; the "
                    "velocities of the frames and joints get the absolute tolerance (doc/multibody.md).");
  prm.declare_entry("Multiplier tolerance", "auto", Patterns::Anything(),
                    "Absolute tolerance of the Lagrange multipliers in IDA's Newton test [N, N m, 1/s] (they are "
                    "not in the error test): 'auto' (the default) or a number from 1e-15 to 1e15. 'auto': the "
                    "joints' multipliers are not in the Newton test either (a multiplier's error moves the "
                    "velocities by (step / mass) times it within the same iteration, and the velocities are "
                    "tested), the bodies' |p| = 1 multipliers are tested against 1e-2. A number tests them all "
                    "against it; round-off in the multipliers grows as 1 / step, so a short step can fail any "
                    "number. Generalised-alpha uses 1e-2 for 'auto' (doc/multibody.md).");
  prm.declare_entry("Maximum order", "auto", Patterns::Anything(),
                    "Largest BDF order IDA may use [-]: 'auto' (the default) or 1 to 5. 'auto': 2 when a "
                    "flexible body has elastic modes (BDF 3 to 5 are not stable for lightly damped vibration "
                    "they step over; BDF 2 is), 5 when every body is rigid.");
  prm.declare_entry("Maximum Newton iterations", "4", Patterns::Integer(1, 100),
                    "Newton iterations per step before IDA rebuilds the Jacobian or cuts the step [-], 1 to 100 "
                    "(IDA's default 4). The slewing beam (6 modes, rtol 1e-5) needs 581 Jacobians with 4 and 309 "
                    "with 10; the laser robot gains nothing.");
  prm.declare_entry("Maximum step", "0", Patterns::Double(0), "Largest time step [s]; 0: no limit.");
  prm.declare_entry("Initial step", "0", Patterns::Double(0), "First time step [s]; 0: IDA's estimate (Radau IIA: 1e-6 s).");
  prm.declare_entry("Maximum steps", "1000000", Patterns::Integer(1), "Internal steps allowed per run [-].");
  prm.declare_entry("Step", "1e-3", Patterns::Double(0),
                    "Generalised-alpha: the time step [s], > 0; the first step when 'Adaptive step' is on.");
  prm.declare_entry("Adaptive step", "false", Patterns::Bool(),
                    "Generalised-alpha: choose the step from a local error estimate (third differences of y') "
                    "against the relative and absolute tolerances, between 1e-12 s and 'Maximum step'.");
  prm.declare_entry("Spectral radius at infinity", "0.8", Patterns::Double(0, 1),
                    "Generalised-alpha: rho_inf [-], 0 to 1: how much of a mode far above 1 / step survives one "
                    "step (1: no numerical damping, 0: annihilated in one step). Second order for every value.");
}

void IntegratorSettings::parse_parameters(ParameterHandler &prm)
{
  const std::string m = prm.get("Method");
  automatic_method = m == "auto";
  method = m == "generalized_alpha" ? IntegrationMethod::generalized_alpha
           : m == "radau"           ? IntegrationMethod::radau
                                    : IntegrationMethod::ida;
  relative_tolerance = prm.get_double("Relative tolerance");
  absolute_tolerance = prm.get_double("Absolute tolerance");
  const std::string v_tol = base::trim(prm.get("Velocity tolerance"));
  automatic_velocity_tolerance = v_tol == "auto";
  velocity_tolerance = automatic_velocity_tolerance ? 0 : base::parse_number(v_tol, "Multibody/Integrator/Velocity tolerance", "'auto' or a number (m/s, rad/s, modal units/s)");
  const std::string m_tol = base::trim(prm.get("Multiplier tolerance"));
  automatic_multiplier_tolerance = m_tol == "auto";
  multiplier_tolerance = automatic_multiplier_tolerance
                           ? 1e-2
                           : base::parse_number(m_tol, "Multibody/Integrator/Multiplier tolerance",
                                                "'auto' or a number (N, N m, 1/s)");
  const std::string order = base::trim(prm.get("Maximum order"));
  automatic_max_order = order == "auto";
  if (!automatic_max_order)
    {
      const double o = base::parse_number(order, "Multibody/Integrator/Maximum order", "'auto' or an integer from 1 to 5");
      if (!(o == 1 || o == 2 || o == 3 || o == 4 || o == 5))
        throw InputError("Multibody/Integrator/Maximum order", "is '" + order + "'; allowed: auto, 1, 2, 3, 4, 5");
      max_order = static_cast<unsigned int>(o);
    }
  max_newton_iterations = prm.get_integer("Maximum Newton iterations");
  max_step = prm.get_double("Maximum step");
  initial_step = prm.get_double("Initial step");
  max_steps = prm.get_integer("Maximum steps");
  step = prm.get_double("Step");
  adaptive_step = prm.get_bool("Adaptive step");
  spectral_radius = prm.get_double("Spectral radius at infinity");
}

std::string IntegratorSettings::method_name() const
{
  return method == IntegrationMethod::ida ? "ida" : method == IntegrationMethod::radau ? "radau" : "generalized_alpha";
}

std::string choose_automatic_settings(const System &system, IntegratorSettings &settings)
{
  // Angular frequency [rad/s] of each velocity coordinate: a flexible body's modal velocities
  // have their mode's; frames and joints' own coordinates have none (0).
  std::vector<double> omega(system.n_v(), 0.0);
  double highest = 0;
  unsigned int n_modes = 0;
  for (unsigned int b = 0; b < system.n_bodies(); ++b)
    {
      const auto *body = dynamic_cast<const FloatingBody *>(&system.body(b));
      if (!body || body->n_modes() == 0) continue;
      const auto w = body->modal_angular_frequencies();
      for (unsigned int k = 0; k < w.size(); ++k)
        {
          omega[system.v_offset(b) + 6 + k] = w[k];
          highest = std::max(highest, w[k]);
        }
      n_modes += w.size();
    }
  std::ostringstream note;
  const auto pattern = system.jacobian_pattern();
  const bool dense = dense_factorisation_is_faster(system, pattern);
  if (settings.automatic_method)
    {
      // Radau IIA is L-stable at order 5: it steps over elastic vibration far below the tolerances
      // without the instability of BDF 3-5 or the low order of BDF 2, and met the error and speed
      // targets of the scenes of prm/bench/default_*.prm where IDA missed them (doc/benchmarks.md).
      // It factorises dense (a real and a complex LU): chosen where the Jacobian is dense anyway
      // and small enough, up to 1000 unknowns (a complex dense LU of 1000 takes about 1 s here);
      // a sparse scene (a chain of flexible links) keeps IDA with KLU. A scene that sets
      // 'Maximum order' has tuned IDA: it keeps IDA.
      settings.automatic_method = false;
      const bool radau = n_modes > 0 && settings.automatic_max_order && dense && system.size() <= 1000;
      settings.method = radau ? IntegrationMethod::radau : IntegrationMethod::ida;
      if (radau)
        note << "method Radau IIA of order 5 (elastic modes up to " << base::number_text(highest / (2 * M_PI))
             << " Hz: L-stable, so vibration within the tolerances is stepped over at order 5)";
      else
        note << "method IDA ("
             << (n_modes == 0                        ? "every body rigid"
                 : !settings.automatic_max_order     ? "'Maximum order' is set, an IDA setting"
                 : system.size() > 1000              ? "more than 1000 unknowns: Radau's dense LUs would cost more"
                                                     : "a sparse Jacobian: KLU, which Radau does not use")
             << ")";
    }
  if (settings.automatic_max_order)
    {
      settings.max_order = settings.method == IntegrationMethod::radau ? 5 : n_modes > 0 ? 2 : 5; // radau: its order
      settings.automatic_max_order = false;
      if (settings.method != IntegrationMethod::ida) {} // only IDA has an order to choose
      else if (n_modes > 0)
        note << (note.tellp() > 0 ? "; " : "") << "BDF order at most 2 (elastic modes up to " << base::number_text(highest / (2 * M_PI))
             << " Hz: BDF 3-5 are unstable for lightly damped vibration they step over)";
      else
        note << (note.tellp() > 0 ? "; " : "") << "BDF order at most 5 (every body rigid)";
    }
  if (settings.automatic_velocity_tolerance)
    {
      settings.automatic_velocity_tolerance = false;
      settings.velocity_tolerance = 0;
      settings.velocity_tolerances.assign(system.n_v(), settings.absolute_tolerance);
      // Frames and joints' own coordinates carry every mode's vibration through the joints.
      // Their tolerance uses the geometric mean of the lowest and the highest modal frequency:
      // the highest (as the modal velocities' rule would give) let the probes drift to 1e-4 of
      // their path on the scenes of prm/bench/default_*.prm, the lowest cost up to 30 times more
      // steps (measurements in doc/benchmarks.md).
      double lowest = highest;
      for (const double w : omega)
        if (w > 0) lowest = std::min(lowest, w);
      const double frame_omega = std::sqrt(lowest * highest);
      for (unsigned int k = 0; k < system.n_v(); ++k)
        settings.velocity_tolerances[k] = settings.absolute_tolerance * std::max(1.0, omega[k] > 0 ? omega[k] : frame_omega);
      if (n_modes > 0)
        note << (note.tellp() > 0 ? "; " : "") << "velocity tolerance of each of the " << n_modes
             << " modal velocities = absolute tolerance x its angular frequency (up to "
             << base::number_text(settings.absolute_tolerance * highest)
             << "), so vibration within the position tolerance is not resolved; of the frames and joints = "
             << base::number_text(settings.absolute_tolerance * std::max(1.0, frame_omega))
             << " (absolute tolerance x the geometric mean of the lowest and highest modal angular frequency)";
    }
  if (settings.automatic_multiplier_tolerance && settings.method == IntegrationMethod::ida)
    note << (note.tellp() > 0 ? "; " : "")
         << "the joints' multipliers not in the Newton test (their error reaches the velocities, which are tested)";
  // The factorisation of the Jacobian (multibody/jacobian_solver.h): said when it is not KLU.
  if (settings.method == IntegrationMethod::radau)
    note << (note.tellp() > 0 ? "; " : "") << "Radau IIA's real and complex Newton matrices (" << system.size()
         << " unknowns) factorised by LAPACK's dense LU";
  else if (dense)
    {
      unsigned int largest = 0;
      for (unsigned int b = 0; b < system.n_bodies(); ++b) largest = std::max(largest, system.body(b).n_v());
      note << (note.tellp() > 0 ? "; " : "") << "the Jacobian (" << system.size() << " unknowns, "
           << std::lround(100 * pattern_fill(pattern)) << " % of its entries in the pattern, the largest dense block "
           << largest << ") factorised by LAPACK's dense LU, not the sparse KLU (faster when the factors are nearly full), "
              "with the positions condensed out first where their Newton blocks are uncoupled";
    }
  return note.str();
}

std::unique_ptr<TimeIntegrator> make_integrator(System &system, const IntegratorSettings &requested)
{
  IntegratorSettings settings = requested;
  choose_automatic_settings(system, settings);
  if (settings.method == IntegrationMethod::generalized_alpha)
    return std::make_unique<GeneralizedAlphaIntegrator>(system, settings);
  if (settings.method == IntegrationMethod::radau) return std::make_unique<RadauIntegrator>(system, settings);
  return std::make_unique<IdaIntegrator>(system, settings);
}
double TimeIntegrator::next_output_time(const double t_now, const double output_interval, const double t_end) const
{
  if (!(output_interval > 0)) return t_end;
  const double tiny = 1e-12 * std::max(1.0, std::abs(t_end));
  double k = std::floor((t_now - output_origin) / output_interval) + 1;
  while (output_origin + (k - 1) * output_interval > t_now + tiny) --k; // floor's round-off
  while (output_origin + k * output_interval <= t_now + tiny) ++k;
  return std::min(output_origin + k * output_interval, t_end);
}

void OneStepIntegrator::set_root_functions(const unsigned int n, RootFunction g)
{
  n_roots = n;
  root_function = std::move(g);
}

void OneStepIntegrator::start_roots(const double t, const State &y, const State &yp)
{
  roots.assign(n_roots, 0);
  g_old.assign(n_roots, 0.0);
  g_new.assign(n_roots, 0.0);
  if (n_roots) root_function(t, y, yp, g_old.data());
}

bool OneStepIntegrator::finish_step(const double t_begin, double &t_now, State &y, State &yp, const double t_end,
                                    const double output_interval, double &next_output, const Observer &output)
{
  State yo, ypo;
  double t_stop = t_now;
  if (n_roots)
    {
      root_function(t_now, y, yp, g_new.data());
      std::vector<double> values(n_roots);
      for (unsigned int i = 0; i < n_roots; ++i)
        if ((g_old[i] < 0 && g_new[i] >= 0) || (g_old[i] > 0 && g_new[i] <= 0))
          {
            double a = t_begin, b = t_now, ga = g_old[i];
            for (int it = 0; it < 200 && b - a > 1e-14 * std::max(1.0, std::abs(b)); ++it)
              {
                const double m = 0.5 * (a + b);
                interpolate(m, yo, ypo);
                root_function(m, yo, ypo, values.data());
                if ((ga < 0) == (values[i] < 0)) a = m, ga = values[i];
                else b = m;
              }
            if (b < t_stop) t_stop = b, std::fill(roots.begin(), roots.end(), 0);
            if (b <= t_stop) roots[i] = g_old[i] < 0 ? 1 : -1;
          }
      g_old = g_new;
    }
  const bool stopped = t_stop < t_now || std::any_of(roots.begin(), roots.end(), [](int r) { return r != 0; });
  if (stopped && t_stop < t_now) // the step ends at the root: its state becomes the current one
    {
      interpolate(t_stop, yo, ypo);
      t_now = t_stop;
      y = yo, yp = ypo;
    }
  if (step_hook) step_hook(t_begin, t_now);
  const double tiny = 1e-12 * std::max(1.0, std::abs(t_end));
  while (output && next_output <= t_now + tiny)
    {
      interpolate(std::min(next_output, t_now), yo, ypo);
      output(std::min(next_output, t_now), yo, ypo);
      if (next_output >= t_end - tiny) break;
      next_output = next_output_time(next_output, output_interval, t_end);
    }
  if (stopped && output) output(t_now, y, yp);
  return stopped;
}
} // namespace flextrack::multibody
