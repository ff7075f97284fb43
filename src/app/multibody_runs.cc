// Consistent start and integration of a multibody scene (multibody_runs.h).
#include <app/multibody_runs.h>
#include <multibody/end_stops.h>
#include <multibody/growth_watch.h>
#include <base/input_error.h>
#include <base/interrupt.h>
#include <base/text.h>
#include <base/solver_error.h>

#include <algorithm>
#include <sstream>

namespace flextrack::app
{
using namespace dealii;

multibody::InitialConditionReport consistent_start(io::MultibodyScene &scene, Vector<double> &y, Vector<double> &yp)
{
  try
    {
      multibody::InitialConditionSettings initial;
      initial.static_equilibrium = scene.settings.static_equilibrium;
      return multibody::consistent_initial_conditions(*scene.system, scene.settings.start_time, y, yp, initial);
    }
  catch (const InputError &e)
    {
      throw e.file().empty() ? e.in_file(scene.file) : e;
    }
}

std::string integrate(multibody::System &system, multibody::TimeIntegrator &integrator, const multibody::SimulationSettings &settings,
                      const std::function<void(double, const Vector<double> &)> &output)
{
  // Checked before each row is written: the rows up to the last one the model could hold stay.
  const multibody::GrowthWatch growth(system);
  try
    {
      return multibody::integrate_with_limits(system, integrator, settings.end_time, settings.output_interval,
                                              [&](const double time, const Vector<double> &state, const Vector<double> &) {
                                                if (const int signal = base::interrupted())
                                                  throw SolverError("interrupted by " + base::signal_name(signal) + " at t = " +
                                                                    base::number_text(time) + " s");
                                                const std::string grown = growth.check(time, state);
                                                if (!grown.empty()) throw SolverError(grown);
                                                output(time, state);
                                              });
    }
  catch (const SolverError &e)
    {
      return e.what();
    }
}

} // namespace flextrack::app
