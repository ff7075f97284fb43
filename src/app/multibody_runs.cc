// Consistent start and integration of a multibody scene (multibody_runs.h).
#include <app/multibody_runs.h>
#include <base/input_error.h>
#include <base/solver_error.h>

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
  if (system.n_limits())
    integrator.set_root_functions(system.n_limits(), [&system](double, const Vector<double> &state, const Vector<double> &,
                                                        double *g) { system.limit_values(state, g); });
  try
    {
      integrator.integrate(settings.end_time, settings.output_interval,
                    [&](const double time, const Vector<double> &state, const Vector<double> &) { output(time, state); });
    }
  catch (const SolverError &e)
    {
      return e.what();
    }
  for (unsigned int i = 0; i < integrator.roots_found().size(); ++i)
    if (integrator.roots_found()[i] != 0)
      {
        Vector<double> state, rate;
        integrator.interpolate(integrator.time(), state, rate);
        std::ostringstream m;
        m << "at t = " << integrator.time() << " s " << system.limit_report(i, state);
        return m.str();
      }
  return "";
}

} // namespace flextrack::app
