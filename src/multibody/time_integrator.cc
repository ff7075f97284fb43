// Integrator settings and the choice of method (time_integrator.h).
#include <multibody/generalized_alpha.h>
#include <multibody/ida_integrator.h>
#include <multibody/time_integrator.h>

#include <algorithm>
#include <cmath>

namespace flextrack::multibody
{
using namespace dealii;

void IntegratorSettings::declare_parameters(ParameterHandler &prm)
{
  prm.declare_entry("Method", "ida", Patterns::Selection("ida|generalized_alpha"),
                    "ida: SUNDIALS IDA, variable-order variable-step BDF (Gear's method), the default; "
                    "generalized_alpha: second-order generalised-alpha with numerical damping of high "
                    "frequencies set by 'Spectral radius at infinity', fixed or adaptive step (doc/multibody.md).");
  prm.declare_entry("Relative tolerance", "1e-6", Patterns::Double(0),
                    "Relative tolerance [-]: IDA's error test; generalised-alpha's Newton test and, with an "
                    "adaptive step, its error test.");
  prm.declare_entry("Absolute tolerance", "1e-8", Patterns::Double(0),
                    "Absolute tolerance, the same for every unknown [m, rad, modal units, and per s] (both methods).");
  prm.declare_entry("Velocity tolerance", "0", Patterns::Double(0),
                    "IDA's absolute tolerance of the velocities [m/s, rad/s, modal units/s], 0 to 1e6; 0: the "
                    "absolute tolerance. A value about the absolute tolerance times the highest angular "
                    "frequency of interest [rad/s] lets IDA step over stiff elastic modes that do not matter.");
  prm.declare_entry("Multiplier tolerance", "1e-2", Patterns::Double(0),
                    "Absolute tolerance of the Lagrange multipliers in IDA's Newton test [N, N m, 1/s] (they "
                    "are not in the error test).");
  prm.declare_entry("Maximum order", "5", Patterns::Integer(1, 5), "Largest BDF order IDA may use [-].");
  prm.declare_entry("Maximum Newton iterations", "4", Patterns::Integer(1, 100),
                    "Newton iterations per step before IDA rebuilds the Jacobian or cuts the step [-], 1 to 100 "
                    "(IDA's default 4). The slewing beam (6 modes, rtol 1e-5) needs 581 Jacobians with 4 and 309 "
                    "with 10; the laser robot gains nothing.");
  prm.declare_entry("Maximum step", "0", Patterns::Double(0), "Largest time step [s]; 0: no limit.");
  prm.declare_entry("Initial step", "0", Patterns::Double(0), "First time step [s]; 0: IDA's estimate.");
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
  method = prm.get("Method") == "generalized_alpha" ? IntegrationMethod::generalized_alpha : IntegrationMethod::ida;
  relative_tolerance = prm.get_double("Relative tolerance");
  absolute_tolerance = prm.get_double("Absolute tolerance");
  velocity_tolerance = prm.get_double("Velocity tolerance");
  multiplier_tolerance = prm.get_double("Multiplier tolerance");
  max_order = prm.get_integer("Maximum order");
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
  return method == IntegrationMethod::ida ? "ida" : "generalized_alpha";
}

std::unique_ptr<TimeIntegrator> make_integrator(System &system, const IntegratorSettings &settings)
{
  if (settings.method == IntegrationMethod::generalized_alpha)
    return std::make_unique<GeneralizedAlphaIntegrator>(system, settings);
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
} // namespace flextrack::multibody
