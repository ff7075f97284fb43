// Constraint and energy monitors (monitors.h).
#include <multibody/monitors.h>

#include <algorithm>
#include <cmath>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
bool same_state(const Vector<double> &a, const Vector<double> &b)
{
  // The step's polynomial passes through the last step's end: equal up to rounding there. A
  // restart (an impact at an end stop) changes the velocities by far more.
  if (a.size() != b.size()) return false;
  for (unsigned int i = 0; i < a.size(); ++i)
    if (!(std::abs(a[i] - b[i]) <= 1e-12 * (1 + std::abs(b[i])))) return false;
  return true;
}
} // namespace

Powers Monitors::powers(const double t, const Vector<double> &y) const
{
  Powers p;
  for (unsigned int f = 0; f < system.n_forces(); ++f)
    {
      const auto q = system.force_q(f, y), v = system.force_v(f, y);
      p.applied += system.force(f).applied_power(q, v, t);
      p.dissipation += system.force(f).dissipation_power(q, v);
    }
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    p.dissipation += system.body(b).dissipation_power(system.q_of(b, y), system.v_of(b, y));
  double own_applied, own_dissipated; // track drive forces and friction
  system.own_force_powers(t, y, own_applied, own_dissipated);
  p.applied += own_applied;
  p.dissipation += own_dissipated;
  // Power of the constraint forces -B^T lambda: sum lambda_r Phi_t,r, where only driven
  // (rheonomic) equations have Phi_t != 0. Only joints with such an equation are evaluated:
  // this runs twice per step, and the whole constraint Jacobian it used to build (a dense
  // equations x velocities matrix) was 31 % of the instructions of a 16-link chain.
  thread_local Vector<double> phi_t;
  const unsigned int l0 = system.n_q() + system.n_v();
  for (unsigned int j = 0; j < system.n_joints(); ++j)
    {
      const Joint &joint = system.joint(j);
      const std::vector<unsigned int> &active = system.active_equations(j);
      if (std::none_of(active.begin(), active.end(), [&](unsigned int k) { return joint.is_driver_equation(k); }))
        continue;
      joint.driver_rates(system.joint_q(j, y), system.own_q_of(j, y), t, phi_t);
      for (unsigned int r = 0; r < active.size(); ++r)
        p.drivers += y[l0 + system.multiplier_offset(j) + r] * phi_t[active[r]];
    }
  return p;
}

Powers Monitors::step_work(const double t0, const double t1) const
{
  // Simpson's rule on IDA's interpolating polynomial of the last step (valid on [t0, t1]).
  Powers w;
  step_powers = {};
  if (!(t1 > t0) || !ida) return w;
  thread_local Vector<double> y; // keeps its storage between steps
  const double t[3] = {t0, 0.5 * (t0 + t1), t1};
  for (unsigned int i = 0; i < 3; ++i)
    {
      ida->interpolate_state(t[i], y);
      step_powers[i] = i == 0 && t[i] == last_time && same_state(y, last_state) ? last_powers : powers(t[i], y);
    }
  last_time = t1;
  last_state = y;
  last_powers = step_powers[2];
  const double h = (t1 - t0) / 6;
  const Powers *p = step_powers.data();
  w.applied = h * (p[0].applied + 4 * p[1].applied + p[2].applied);
  w.drivers = h * (p[0].drivers + 4 * p[1].drivers + p[2].drivers);
  w.dissipation = h * (p[0].dissipation + 4 * p[1].dissipation + p[2].dissipation);
  return w;
}

Powers Monitors::partial_step_work(const double t) const
{
  // The quadratic through Simpson's three powers of the step, integrated from its start to t:
  // no new evaluation (the rows inside a step used to cost three), and exactly Simpson's sum at
  // the step's end. tau = (t - t0) / h; the integrals of the Lagrange basis from 0 to tau.
  const double h = step_end - step_begin, tau = (t - step_begin) / h;
  const double c0 = tau * (1 + tau * (-1.5 + tau * 2.0 / 3)), cm = tau * tau * (2 - tau * 4.0 / 3),
               c1 = tau * tau * (-0.5 + tau * 2.0 / 3);
  const Powers *p = step_powers.data();
  Powers w;
  w.applied = h * (c0 * p[0].applied + cm * p[1].applied + c1 * p[2].applied);
  w.drivers = h * (c0 * p[0].drivers + cm * p[1].drivers + c1 * p[2].drivers);
  w.dissipation = h * (c0 * p[0].dissipation + cm * p[1].dissipation + c1 * p[2].dissipation);
  return w;
}

void Monitors::attach(TimeIntegrator &integrator)
{
  ida = &integrator;
  integrator.set_step_hook([this](const double t0, const double t1) {
    const Powers w = step_work(t0, t1);
    work_applied += w.applied;
    work_drivers += w.drivers;
    dissipated += w.dissipation;
    step_begin = t0;
    step_end = t1;
    step_total = w;
  });
}

MonitorValues Monitors::evaluate(const double t, const Vector<double> &y) const
{
  MonitorValues m;
  m.time = t;
  // Every joint equation, the dropped (redundant) ones included: they hold only as long as they
  // depend on the others, and a monitor of the active ones alone would not see them fail.
  system.constraint_residuals(t, y, m.position_residual, m.velocity_residual);
  for (unsigned int i = system.n_q() + system.n_v() + system.n_lambda(); i < system.size(); ++i)
    m.max_mu = std::max(m.max_mu, std::abs(y[i]));
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      const Body &body = system.body(b);
      const double *q = system.q_of(b, y), *vb = system.v_of(b, y);
      m.normalisation_drift = std::max(m.normalisation_drift, std::abs(std::sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]) - 1));
      m.kinetic += body.kinetic_energy(q, vb);
      m.gravity += body.gravity_potential(q, system.gravity());
      m.strain += body.strain_energy(q);
    }
  for (unsigned int f = 0; f < system.n_forces(); ++f) m.springs += system.force(f).potential_energy(system.force_q(f, y));
  m.work_applied = work_applied;
  m.work_drivers = work_drivers;
  m.dissipated = dissipated + system.impact_losses(); // impacts at end stops take (1 - e^2) of their energy
  // The works are summed up to the end of IDA's last step, t_n; an output row at t < t_n is
  // interpolated back into that step, so the part of the step after t must come off again
  // (else the row compares E(t) with the work up to t_n: up to one step's work of error, which
  // made the driven slider-crank's balance jump by 5-8 % at rows inside long steps).
  if (ida && t > step_begin && t < step_end)
    {
      const Powers part = partial_step_work(t);
      m.work_applied -= step_total.applied - part.applied;
      m.work_drivers -= step_total.drivers - part.drivers;
      m.dissipated -= step_total.dissipation - part.dissipation;
    }
  return m;
}

double EnergyBalance::error(const MonitorValues &now)
{
  const double balance = now.energy() - start.energy() - (now.work_applied + now.work_drivers - now.dissipated);
  scale = std::max({scale, now.kinetic, std::abs(now.gravity), std::abs(now.strain), std::abs(now.springs),
                    std::abs(now.work_applied), std::abs(now.work_drivers), std::abs(now.dissipated)});
  largest_balance = std::max(largest_balance, std::abs(balance));
  return balance / scale;
}
} // namespace flextrack::multibody
