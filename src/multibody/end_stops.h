// Integration to an end time with the joints' limits (the ends of tracks) as events: a limit
// either ends the run (the default: the report says where) or is an end stop. At an end stop the
// contact hits with a restitution coefficient e: the velocities jump by the impulse through the
// joints that gives s'+ = -e s'- (project_velocities: the change of least kinetic-energy norm,
// so the impact takes (1 - e^2) of the kinetic energy of the relative motion, counted as
// dissipated by the monitors); a rebound slower than the stop's hold speed is held instead (the
// contact's velocity row reads s' = 0, System::set_held) until the stop would have to pull (its
// limit function is then the push of the stop, which changes sign there). After each jump the
// accelerations and multipliers are made consistent and the integrator restarts.
#pragma once

#include <multibody/system.h>
#include <multibody/time_integrator.h>

#include <string>

namespace flextrack::multibody
{
/// Integrates from the integrator's time to @p t_end, calling @p output at its output times (and
/// at each event). Returns "" at @p t_end, else the report of the limit that ended the run, or of
/// the redundant equation dropped at the start that stopped holding (System::dropped_equation_margin).
/// Throws SolverError if the integration fails.
std::string integrate_with_limits(System &system, TimeIntegrator &integrator, double t_end, double output_interval,
                                  const TimeIntegrator::Observer &output);
} // namespace flextrack::multibody
