// Dense pieces of the system in velocity coordinates - mass matrix, generalised forces,
// constraint values and Jacobians, position updates - used by the consistent initial
// conditions, the monitors and the linearisation (sizes there are small: n_v, not n_y).
#include <multibody/system.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

void System::mass_matrix(const Vector<double> &y, FullMatrix<double> &M) const
{
  M.reinit(nv, nv);
  FullMatrix<double> Mb;
  for (const auto &b : bodies)
    {
      if (b.body->is_ground()) continue;
      b.body->mass_matrix((y.begin() + (b.q)), Mb);
      for (unsigned int i = 0; i < Mb.m(); ++i)
        for (unsigned int k = 0; k < Mb.n(); ++k) M(b.v + i, b.v + k) = Mb(i, k);
    }
}

void System::generalized_forces(const double t, const Vector<double> &y, Vector<double> &Q,
                                const Vector<double> *v_dot) const
{
  Q.reinit(nv);
  for (const auto &b : bodies)
    if (!b.body->is_ground())
      b.body->forces((y.begin() + (b.q)), (y.begin() + (nq + b.v)), g, (Q.begin() + (b.v)),
                     v_dot ? v_dot->begin() + b.v : nullptr);
  for (unsigned int f = 0; f < forces.size(); ++f)
    {
      std::vector<double *> Qb;
      for (const unsigned int b : forces[f].body_index) Qb.push_back(bodies[b].body->n_v() ? &Q[bodies[b].v] : nullptr);
      forces[f].force->add_forces(force_q(f, y), force_v(f, y), t, Qb);
    }
  std::vector<double> applied, dissipative;
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      own_forces(j, t, y, applied, dissipative);
      for (unsigned int i = 0; i < applied.size(); ++i) Q[joints[j].own_v + i] += applied[i] + dissipative[i];
    }
}

void System::own_forces(const unsigned int j, const double t, const Vector<double> &y, std::vector<double> &applied,
                        std::vector<double> &dissipative) const
{
  const JointSlot &s = joints[j];
  const unsigned int n_own = s.joint->n_own_coordinates();
  applied.assign(n_own, 0.0);
  dissipative.assign(n_own, 0.0);
  if (n_own) s.joint->own_forces(y.begin() + s.own_q, y.begin() + nq + s.own_v, t, applied.data(), dissipative.data());
}

void System::own_force_powers(const double t, const Vector<double> &y, double &applied_power,
                              double &dissipated_power) const
{
  applied_power = dissipated_power = 0;
  std::vector<double> applied, dissipative;
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      own_forces(j, t, y, applied, dissipative);
      const double *v = y.begin() + nq + joints[j].own_v;
      for (unsigned int i = 0; i < applied.size(); ++i)
        {
          applied_power += applied[i] * v[i];
          dissipated_power -= dissipative[i] * v[i];
        }
    }
}

unsigned int System::n_limits() const
{
  unsigned int n = 0;
  for (const auto &j : joints) n += j.joint->n_limits();
  return n;
}

void System::limit_values(const Vector<double> &y, double *g) const
{
  for (const auto &j : joints)
    if (j.joint->n_limits())
      {
        j.joint->limits(y.begin() + j.own_q, g);
        g += j.joint->n_limits();
      }
}

std::pair<unsigned int, unsigned int> System::limit_owner(unsigned int i) const
{
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      if (i < joints[j].joint->n_limits()) return {j, i};
      i -= joints[j].joint->n_limits();
    }
  Assert(false, ExcMessage("no such limit"));
  return {0, 0};
}

Joint::EndStop System::end_stop(const unsigned int i, unsigned int &velocity_index) const
{
  const auto [j, k] = limit_owner(i);
  const Joint::EndStop e = joints[j].joint->end_stop(k);
  velocity_index = nq + joints[j].own_v + e.coordinate;
  return e;
}

void System::set_held(const unsigned int i, const bool held)
{
  held_limit.resize(n_limits(), 0);
  held_velocity.resize(nv, 0);
  unsigned int v = 0;
  end_stop(i, v);
  held_limit[i] = held;
  held_velocity[v - nq] = held;
}

double System::stop_force(const unsigned int j, const unsigned int coordinate, const double t, const Vector<double> &y) const
{
  const JointSlot &s = joints[j];
  JointEvaluation e;
  s.joint->evaluate(joint_q(j, y), y.begin() + s.own_q, t, e);
  std::vector<double> applied, dissipative;
  own_forces(j, t, y, applied, dissipative);
  const double *lambda = y.begin() + nq + nv + s.multiplier;
  double push = -(applied[coordinate] + dissipative[coordinate]);
  for (unsigned int r = 0; r < s.active.size(); ++r) push += e.B_own(s.active[r], coordinate) * lambda[r];
  return push;
}

void System::limit_values(const double t, const Vector<double> &y, double *g) const
{
  limit_values(y, g);
  for (unsigned int i = 0; i < held_limit.size(); ++i)
    if (held_limit[i])
      {
        const auto [j, k] = limit_owner(i);
        const Joint::EndStop e = joints[j].joint->end_stop(k);
        // The stop at the lower end pushes towards +s, the one at the upper end towards -s.
        const double push = stop_force(j, e.coordinate, t, y);
        g[i] = e.upper ? -push : push;
      }
}

double System::kinetic_energy(const Vector<double> &y) const
{
  double T = 0;
  for (unsigned int b = 1; b < bodies.size(); ++b) T += bodies[b].body->kinetic_energy(q_of(b, y), v_of(b, y));
  return T;
}

std::string System::limit_report(unsigned int i, const Vector<double> &y) const
{
  for (const auto &j : joints)
    {
      if (i < j.joint->n_limits()) return j.joint->limit_report(i, y.begin() + j.own_q, y.begin() + nq + j.own_v);
      i -= j.joint->n_limits();
    }
  return "limit " + std::to_string(i);
}

std::vector<std::pair<unsigned int, unsigned int>> System::constraint_rows(const bool all_equations) const
{
  std::vector<std::pair<unsigned int, unsigned int>> rows;
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      if (all_equations)
        for (unsigned int k = 0; k < joints[j].joint->n_equations(); ++k) rows.emplace_back(j, k);
      else
        for (const unsigned int k : joints[j].active) rows.emplace_back(j, k);
    }
  return rows;
}

void System::constraints(const double t, const Vector<double> &y, const bool all_equations, Vector<double> &phi,
                         FullMatrix<double> &B, Vector<double> &phi_t) const
{
  const auto rows = constraint_rows(all_equations);
  phi.reinit(rows.size());
  phi_t.reinit(rows.size());
  B.reinit(rows.size(), nv);
  unsigned int r0 = 0;
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      const JointSlot &s = joints[j];
      JointEvaluation e;
      s.joint->evaluate(joint_q(j, y), s.joint->n_own_coordinates() ? (y.begin() + (s.own_q)) : nullptr, t, e);
      std::vector<unsigned int> eqs;
      if (all_equations)
        for (unsigned int k = 0; k < s.joint->n_equations(); ++k) eqs.push_back(k);
      else
        eqs = s.active;
      for (unsigned int r = 0; r < eqs.size(); ++r)
        {
          phi[r0 + r] = e.phi[eqs[r]];
          phi_t[r0 + r] = e.phi_t[eqs[r]];
          for (unsigned int m = 0; m < s.body_index.size(); ++m)
            for (unsigned int c = 0; c < e.B[m].n(); ++c) B(r0 + r, bodies[s.body_index[m]].v + c) += e.B[m](eqs[r], c);
          for (unsigned int c = 0; c < e.B_own.n(); ++c) B(r0 + r, s.own_v + c) += e.B_own(eqs[r], c);
        }
      r0 += eqs.size();
    }
}

void System::constraint_residuals(const double t, const Vector<double> &y, double &position, double &velocity) const
{
  // The monitors ask for these at every output row: a dense equations x n_v matrix built for
  // them was a third of a row's cost.
  position = velocity = 0;
  const auto keep_largest = [](double &largest, const double x) { // a NaN stays
    if (!std::isnan(largest) && !(std::abs(x) <= largest)) largest = std::abs(x);
  };
  thread_local JointResidualTerms terms; // keeps its storage between calls
  thread_local std::vector<const double *> v;
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      const JointSlot &s = joints[j];
      const bool own = s.joint->n_own_coordinates();
      v.clear();
      for (const unsigned int b : s.body_index) v.push_back(v_of(b, y));
      s.joint->residual_terms(joint_q(j, y), own ? (y.begin() + s.own_q) : nullptr, t, v,
                              own ? (y.begin() + (nq + s.own_v)) : nullptr, nullptr, nullptr, terms);
      for (unsigned int k = 0; k < s.joint->n_equations(); ++k)
        {
          keep_largest(position, terms.phi[k]);
          keep_largest(velocity, terms.rate[k]);
        }
    }
}

double System::scaled_residual(const double t, const Vector<double> &y, const bool of_dropped, unsigned int *worst) const
{
  double largest = 0;
  unsigned int r0 = 0;
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      const JointSlot &s = joints[j];
      const unsigned int n = s.joint->n_equations();
      if (of_dropped && s.active.size() == n)
        {
          r0 += n;
          continue; // nothing dropped here: no need to evaluate it
        }
      JointEvaluation e;
      s.joint->evaluate(joint_q(j, y), s.joint->n_own_coordinates() ? (y.begin() + (s.own_q)) : nullptr, t, e);
      for (unsigned int k = 0; k < n; ++k)
        {
          const bool active = std::find(s.active.begin(), s.active.end(), k) != s.active.end();
          if (active == of_dropped) continue;
          const double scale = r0 + k < equation_scale.size() ? equation_scale[r0 + k] : 1.0;
          const double value = std::abs(e.phi[k]) / scale;
          if (!(value <= largest)) // NaN counts as the largest
            {
              largest = value;
              if (worst) *worst = r0 + k;
            }
        }
      r0 += n;
    }
  return largest;
}

double System::dropped_equation_margin(const double t, const Vector<double> &y) const
{
  if (dropped.empty()) return 1;
  const double allowed = dropped_equation_tolerance + 100 * scaled_residual(t, y, false);
  const double margin = allowed - scaled_residual(t, y, true);
  return std::isnan(margin) ? -1.0 : margin;
}

std::string System::dropped_equation_report(const double t, const Vector<double> &y) const
{
  unsigned int worst = 0;
  const double active = scaled_residual(t, y, false), value = scaled_residual(t, y, true, &worst);
  const auto [j, k] = constraint_rows(true)[worst];
  const double scale = worst < equation_scale.size() ? equation_scale[worst] : 1.0;
  std::ostringstream s;
  s << std::setprecision(3) << "the equation '" << joints[j].joint->equation_name(k) << "' of joint '"
    << joints[j].joint->name() << "', dropped at the start as redundant, no longer holds: |Phi| = " << value * scale
    << " (m or rad), allowed " << (dropped_equation_tolerance + 100 * active) * scale
    << ". It depended on the other equations at the start but not here: the motion has passed a singular "
       "configuration (a dead point, links in line). What to change: keep the mechanism away from it, or "
       "model the loop without redundant equations (e.g. a spherical or universal joint for one revolute joint)";
  return s.str();
}

void System::move_positions(Vector<double> &y, const Vector<double> &dx) const
{
  Vector<double> rate(nq), x(size());
  for (unsigned int i = 0; i < nv; ++i) x[nq + i] = dx[i];
  for (unsigned int i = 0; i < nq; ++i) x[i] = y[i]; // T(q) at the current q
  coordinate_rates(x, rate);
  for (unsigned int i = 0; i < nq; ++i) y[i] += rate[i];
  for (const auto &b : bodies)
    {
      if (b.body->is_ground()) continue;
      double *p = (y.begin() + (b.q + 3));
      const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3]);
      for (unsigned int i = 0; i < 4; ++i) p[i] /= n;
    }
}

void System::coordinate_rates(const Vector<double> &y, Vector<double> &q_dot) const
{
  q_dot.reinit(nq);
  for (const auto &b : bodies)
    if (!b.body->is_ground()) b.body->coordinate_rates((y.begin() + (b.q)), (y.begin() + (nq + b.v)), &q_dot[b.q]);
  for (const auto &j : joints)
    for (unsigned int k = 0; k < j.joint->n_own_coordinates(); ++k) q_dot[j.own_q + k] = y[nq + j.own_v + k];
}
} // namespace flextrack::multibody
