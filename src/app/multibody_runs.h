// Pieces shared by the commands that integrate a multibody scene (run, bench): consistent
// initial conditions and an integration to the scene's end time that returns why it stopped.
#pragma once

#include <io/multibody_scene.h>
#include <multibody/initial_conditions.h>
#include <multibody/time_integrator.h>

#include <deal.II/lac/vector.h>

#include <functional>
#include <string>

namespace flextrack::app
{
/// Consistent initial conditions of @p scene at its start time; InputError naming the scene file.
multibody::InitialConditionReport consistent_start(io::MultibodyScene &scene, dealii::Vector<double> &y,
                                                   dealii::Vector<double> &yp);

/// Integrates with @p integrator (initialised) to the end time of @p settings, calling @p output at
/// every output time after the start. Returns "" when the end time is reached, else why not: the
/// solver failure, or where the run stopped at the end of a track (root finding on the limits).
std::string integrate(multibody::System &system, multibody::TimeIntegrator &integrator,
                      const multibody::SimulationSettings &settings,
                      const std::function<void(double, const dealii::Vector<double> &)> &output);
} // namespace flextrack::app
