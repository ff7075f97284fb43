// End stops and limits as events of the integration (end_stops.h).
#include <multibody/end_stops.h>
#include <multibody/initial_conditions.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flextrack::multibody
{
using dealii::Vector;

namespace
{
/// Events at end stops before a run gives up (a contact that chatters between them).
constexpr unsigned long max_stop_events = 100000;

/// What the contact at the stop of limit @p i does at (t, y): an impact with restitution, held at
/// the stop when the rebound is slower than the stop's hold speed. Returns false if the contact
/// is moving away from the stop (a root of its limit on the way in: nothing to do).
bool hit_stop(System &system, const unsigned int i, const double t, Vector<double> &y)
{
  unsigned int v = 0;
  const Joint::EndStop stop = system.end_stop(i, v);
  const double speed = y[v];
  if (!(stop.upper ? speed > 0 : speed < 0)) return false;
  double rebound = -stop.restitution * speed;
  if (std::abs(rebound) <= stop.hold_speed)
    {
      system.set_held(i, true);
      rebound = 0;
    }
  const double before = system.kinetic_energy(y);
  project_velocities(system, t, y, {{v, rebound}});
  system.add_impact_loss(before - system.kinetic_energy(y));
  return true;
}
} // namespace

std::string integrate_with_limits(System &system, TimeIntegrator &integrator, const double t_end, const double output_interval,
                                  const TimeIntegrator::Observer &output)
{
  const unsigned int n_limits = system.n_limits();
  // One more root function while equations are dropped as redundant: positive while they still
  // hold (System::dropped_equation_margin), so the run stops where they stop depending on the others.
  const bool watch_dropped = !system.dropped_equations().empty();
  if (n_limits + watch_dropped)
    integrator.set_root_functions(n_limits + watch_dropped,
                                  [&system, n_limits, watch_dropped](const double t, const Vector<double> &state,
                                                                     const Vector<double> &, double *g) {
                                    system.limit_values(t, state, g);
                                    if (watch_dropped) g[n_limits] = system.dropped_equation_margin(t, state);
                                  });
  for (unsigned long events = 0;; ++events)
    {
      integrator.integrate(t_end, output_interval, output);
      const std::vector<int> roots = integrator.roots_found();
      if (std::none_of(roots.begin(), roots.end(), [](const int r) { return r != 0; })) return "";
      const double t = integrator.time();
      Vector<double> state, rate;
      integrator.interpolate(t, state, rate);
      bool jumped = false;
      if (watch_dropped && roots.size() > n_limits && roots[n_limits] != 0)
        {
          std::ostringstream m;
          m << "at t = " << t << " s " << system.dropped_equation_report(t, state);
          return m.str();
        }
      for (unsigned int i = 0; i < n_limits; ++i)
        {
          if (roots[i] == 0) continue;
          unsigned int v = 0;
          // A contact that reaches the end of its track at the end time (a passage timed to end
          // there, End time = L / c) has finished, not failed (issue 25, item 7: exit 3 before).
          if (system.end_stop(i, v).stop_run)
            {
              if (t_end - t <= 1e-9 * std::max({std::abs(t_end), output_interval, 1e-3})) return "";
              std::ostringstream m;
              m << "at t = " << t << " s " << system.limit_report(i, state);
              return m.str();
            }
          if (system.is_held(i)) // the stop would have to pull: the contact leaves it
            {
              system.set_held(i, false);
              jumped = true;
            }
          else
            jumped |= hit_stop(system, i, t, state);
        }
      if (!jumped) continue; // a limit crossed on the way in from a stop
      if (events >= max_stop_events)
        {
          std::ostringstream m;
          m << "at t = " << t << " s more than " << max_stop_events
            << " impacts at end stops: a contact chatters at a stop; raise its 'Hold speed' or lower its 'Restitution'";
          return m.str();
        }
      consistent_derivatives(system, t, state, rate);
      // A contact just held whose stop would pull at once is released again.
      std::vector<double> g(n_limits);
      system.limit_values(t, state, g.data());
      bool released = false;
      for (unsigned int i = 0; i < n_limits; ++i)
        if (system.is_held(i) && g[i] < 0)
          {
            system.set_held(i, false);
            released = true;
          }
      if (released) consistent_derivatives(system, t, state, rate);
      integrator.reinitialize(t, state, rate);
    }
}

} // namespace flextrack::multibody
