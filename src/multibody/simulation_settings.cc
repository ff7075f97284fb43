// Parameters of `subsection Multibody` (simulation_settings.h).
#include <base/input_error.h>
#include <base/text.h>
#include <multibody/simulation_settings.h>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
/// A scene with more instances than this is almost certainly a mistake (or hostile); every
/// instance costs a ParameterHandler subsection.
constexpr std::size_t max_instances = 1000;

const char *const list_entries[4][2] = {{"Bodies", "body"}, {"Joints", "joint"}, {"Forces", "force"}, {"Probes", "probe"}};
} // namespace

void SceneNames::declare_name_lists(ParameterHandler &prm)
{
  prm.enter_subsection("Multibody");
  prm.declare_entry("Bodies", "", Patterns::Anything(),
                    "Names of the moving bodies, separated by commas (letters, digits, '_'); each body NAME "
                    "is described in 'subsection Body NAME'. The fixed frame 'ground' is always there and "
                    "is not listed. At most 1000 [-].");
  prm.declare_entry("Joints", "", Patterns::Anything(),
                    "Names of the joints; each in 'subsection Joint NAME'. At most 1000 [-].");
  prm.declare_entry("Forces", "", Patterns::Anything(),
                    "Names of the applied loads and spring-dampers; each in 'subsection Force NAME'. At most "
                    "1000 [-].");
  prm.declare_entry("Probes", "", Patterns::Anything(),
                    "Names of the probes (marker positions and velocities written at every output time); "
                    "each in 'subsection Probe NAME'. At most 1000 [-].");
  prm.leave_subsection();
}

SceneNames SceneNames::parse_name_lists(ParameterHandler &prm)
{
  SceneNames names;
  std::vector<std::string> *lists[4] = {&names.bodies, &names.joints, &names.forces, &names.probes};
  prm.enter_subsection("Multibody");
  for (unsigned int i = 0; i < 4; ++i)
    {
      const std::string entry = std::string("Multibody/") + list_entries[i][0];
      *lists[i] = base::parse_name_list(prm.get(list_entries[i][0]), entry, std::string(list_entries[i][1]) + " name");
      if (lists[i]->size() > max_instances)
        throw InputError(entry, "names " + std::to_string(lists[i]->size()) + " instances; at most 1000 are allowed");
    }
  prm.leave_subsection();
  for (const auto &b : names.bodies)
    if (b == ground_name)
      throw InputError("Multibody/Bodies", "'ground' is the fixed frame every scene has; do not list it");
  return names;
}

void SimulationSettings::declare_parameters(ParameterHandler &prm)
{
  prm.enter_subsection("Multibody");
  prm.declare_entry("Gravity", "0, 0, -9.81", Patterns::Anything(), "Gravitational acceleration, global [m/s^2].");
  prm.declare_entry("Start time", "0", Patterns::Double(), "Time at the initial state [s].");
  prm.declare_entry("End time", "1", Patterns::Double(), "Time at which the run ends [s] (> start time).");
  prm.declare_entry("Output interval", "0.01", Patterns::Double(0),
                    "Time between output rows (probes, results.h5) [s]; 0: only the start and the end.");
  prm.declare_entry("Flexible bodies rigid", "false", Patterns::Bool(),
                    "Treat every flexible body as rigid with the same mass properties (m, s, J_O; no modes), "
                    "to compare the same scene with and without flexibility [-].");
  prm.declare_entry("Rigid reference", "false", Patterns::Bool(),
                    "'flextrack run' runs the scene a second time with every body rigid (as 'Flexible bodies "
                    "rigid = true': the nominal path) and writes deviation.csv (each probe's rigid position and "
                    "its distance from the probe of the run [m] at the same output times), the largest "
                    "deviation per probe (printed, summary.json) and deviation.png (gnuplot: both paths and the "
                    "deviation in time). Needs at least one probe [-].");
  prm.declare_entry("Initial state", "as given", Patterns::Selection("as given|static equilibrium"),
                    "'as given': the bodies' Position, orientation, Velocity, Angular velocity, Modal "
                    "coordinates and Modal velocities, made consistent with the joints. 'static equilibrium': "
                    "the configuration at rest under gravity and the loads and driver positions at the start "
                    "time (frames, modal coordinates and joint coordinates solved by a damped Newton "
                    "iteration on M v' = 0 = Q - B^T lambda with the joint equations; the given positions are "
                    "the first guess, the given velocities are ignored; drivers moving at the start time give "
                    "their velocity). Refused when there is no equilibrium or it is not unique (a mechanism "
                    "under these loads) [-].");
  prm.enter_subsection("Integrator");
  IntegratorSettings::declare_parameters(prm);
  prm.leave_subsection();
  prm.leave_subsection();
}

SimulationSettings SimulationSettings::parse_parameters(ParameterHandler &prm)
{
  SimulationSettings s;
  prm.enter_subsection("Multibody");
  const auto g = base::parse_vector3(prm.get("Gravity"), "Multibody/Gravity", "m/s^2");
  s.gravity = Vector3({g[0], g[1], g[2]});
  s.start_time = prm.get_double("Start time");
  s.end_time = prm.get_double("End time");
  s.output_interval = prm.get_double("Output interval");
  s.flexible_as_rigid = prm.get_bool("Flexible bodies rigid");
  s.rigid_reference = prm.get_bool("Rigid reference");
  s.static_equilibrium = prm.get("Initial state") == "static equilibrium";
  prm.enter_subsection("Integrator");
  s.integrator.parse_parameters(prm);
  prm.leave_subsection();
  prm.leave_subsection();
  // Zero tolerances are legal numbers but leave IDA an error weight of 1/0; tolerances below
  // round-off (1e-300) left IDA stuck at the start ("tstop = 1 is behind current t = 0"), and
  // bench scales the absolute tolerances by rtol / (the scene's rtol), which a 0 made infinite.
  const auto &in = s.integrator;
  using base::number_text;
  if (!(in.absolute_tolerance >= 1e-15))
    throw InputError("Multibody/Integrator/Absolute tolerance", "must be >= 1e-15 (m, rad, modal units and per s)");
  if (!(in.velocity_tolerance == 0 || (in.velocity_tolerance >= 1e-15 && in.velocity_tolerance <= 1e6)))
    throw InputError("Multibody/Integrator/Velocity tolerance", "must be auto, 0 (the absolute tolerance) or from 1e-15 "
                                                               "to 1e6 (m/s, rad/s, modal units/s)");
  if (!(in.multiplier_tolerance >= 1e-15 && in.multiplier_tolerance <= 1e15))
    throw InputError("Multibody/Integrator/Multiplier tolerance", "must be auto or from 1e-15 to 1e15 (N, N m, 1/s)");
  if (!(in.relative_tolerance >= 1e-14 && in.relative_tolerance < 1))
    throw InputError("Multibody/Integrator/Relative tolerance", "must be from 1e-14 (about 50 times the round-off of "
                                                               "double precision) to below 1");
  if (!(s.end_time > s.start_time))
    throw InputError("Multibody/End time", "must be later than the start time (" + std::to_string(s.start_time) + " s)");
  // Steps far below the run's duration cannot make progress in double precision (t + h == t
  // near t = 1 for h < 1e-16); 1e-10 of the run leaves any method 1e10 steps, beyond every use.
  const double span = s.end_time - s.start_time, smallest = 1e-10 * span;
  const std::string range = "(s), from " + number_text(smallest) + " s (1e-10 of the run) to the run's " + number_text(span) + " s";
  if (!(in.step >= smallest) || !(in.step <= std::max(span, 1e3)))
    throw InputError("Multibody/Integrator/Step", "must be from " + number_text(smallest) + " s (1e-10 of the run) to " +
                                                  number_text(std::max(span, 1e3)) + " s");
  if (in.initial_step != 0 && !(in.initial_step >= smallest && in.initial_step <= span))
    throw InputError("Multibody/Integrator/Initial step", "must be 0 (IDA's estimate) or " + range);
  if (in.max_step != 0 && !(in.max_step >= smallest))
    throw InputError("Multibody/Integrator/Maximum step", "must be 0 (no limit) or at least " + number_text(smallest) +
                                                          " s (1e-10 of the run)");
  if (s.integrator.method == IntegrationMethod::generalized_alpha && !s.integrator.adaptive_step &&
      (s.end_time - s.start_time) / s.integrator.step > 1e8)
    throw InputError("Multibody/Integrator/Step", "gives more than 1e8 steps over the run; choose a longer step or "
                                                  "'Adaptive step' = true");
  if (s.output_interval > 0 && (s.end_time - s.start_time) / s.output_interval > 1e7)
    throw InputError("Multibody/Output interval", "asks for more than 1e7 output rows; choose a longer interval");
  return s;
}
} // namespace flextrack::multibody
