// The multibody system: layout of the unknowns and the GGL residual, element by element
// (system.h). The Jacobian and its factorisation are in system_jacobian.cc.
#include <base/input_error.h>
#include <multibody/jacobian_solver.h>
#include <multibody/system.h>

namespace flextrack::multibody
{
using namespace dealii;

System::System(const Vector3 &gravity) : g(gravity)
{
  bodies.push_back({std::make_unique<Ground>("ground"), 0, 0, 0});
}

System::~System() = default;

const Body &System::add_body(std::unique_ptr<Body> body)
{
  Assert(!finalized, ExcMessage("add bodies before finalize()"));
  if (find_body(body->name())) throw InputError("Body " + body->name(), "a body of that name exists already");
  bodies.push_back({std::move(body), 0, 0, 0});
  return *bodies.back().body;
}

void System::add_joint(std::unique_ptr<Joint> joint)
{
  Assert(!finalized, ExcMessage("add joints before finalize()"));
  for (const auto &j : joints)
    if (j.joint->name() == joint->name()) throw InputError("Joint " + joint->name(), "a joint of that name exists already");
  JointSlot slot;
  for (const Body *b : joint->bodies()) slot.body_index.push_back(body_index(*b));
  slot.joint = std::move(joint);
  joints.push_back(std::move(slot));
}

void System::add_force(std::unique_ptr<Force> force)
{
  Assert(!finalized, ExcMessage("add forces before finalize()"));
  ForceSlot slot;
  for (const Body *b : force->bodies()) slot.body_index.push_back(body_index(*b));
  slot.force = std::move(force);
  forces.push_back(std::move(slot));
}

const Body *System::find_body(const std::string &name) const
{
  for (const auto &b : bodies)
    if (b.body->name() == name) return b.body.get();
  return nullptr;
}

BodyLookup System::body_lookup() const
{
  return [this](const std::string &name) { return find_body(name); };
}

unsigned int System::body_index(const Body &b) const
{
  for (unsigned int i = 0; i < bodies.size(); ++i)
    if (bodies[i].body.get() == &b) return i;
  throw InputError("Body " + b.name(), "is not a body of this system (add the body before its joints and forces)");
}

void System::finalize()
{
  nq = nv = 0;
  for (auto &b : bodies)
    {
      b.q = nq;
      b.v = nv;
      nq += b.body->n_q();
      nv += b.body->n_v();
    }
  n_own_q = 0;
  for (auto &j : joints)
    {
      j.own_q = nq;
      j.own_v = nv;
      nq += j.joint->n_own_coordinates();
      nv += j.joint->n_own_coordinates();
      n_own_q += j.joint->n_own_coordinates();
      j.active.clear();
      for (unsigned int k = 0; k < j.joint->n_equations(); ++k) j.active.push_back(k);
    }
  dropped.clear();
  finalized = true;
  layout_multipliers();
}

void System::drop_equations(const std::vector<std::pair<unsigned int, unsigned int>> &equations)
{
  for (const auto &[j, k] : equations)
    {
      auto &active = joints[j].active;
      const auto it = std::find(active.begin(), active.end(), k);
      if (it == active.end()) continue;
      active.erase(it);
      dropped.push_back({joints[j].joint->name(), k, joints[j].joint->equation_name(k)});
    }
  layout_multipliers();
}

void System::layout_multipliers()
{
  nlambda = 0;
  for (auto &j : joints)
    {
      j.multiplier = nlambda;
      nlambda += j.active.size();
    }
  nmu = nlambda;
  for (auto &b : bodies)
    if (!b.body->is_ground()) b.normalisation = nmu++;
  build_element_indices();
  solver.reset();
}

void System::build_element_indices()
{
  const unsigned int v0 = nq, l0 = nq + nv, m0 = nq + nv + nlambda;
  auto add_range = [](std::vector<unsigned int> &to, const unsigned int start, const unsigned int n) {
    for (unsigned int i = 0; i < n; ++i) to.push_back(start + i);
  };
  body_elements.assign(bodies.size(), {});
  for (unsigned int b = 1; b < bodies.size(); ++b)
    {
      const BodySlot &s = bodies[b];
      ElementIndices &e = body_elements[b];
      add_range(e.rows, s.q, s.body->n_q());
      add_range(e.rows, v0 + s.v, s.body->n_v());
      e.rows.push_back(m0 + s.normalisation);
      add_range(e.columns, s.q, s.body->n_q());
      add_range(e.columns, v0 + s.v, s.body->n_v());
    }
  joint_elements.assign(joints.size(), {});
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      const JointSlot &s = joints[j];
      ElementIndices &e = joint_elements[j];
      const unsigned int n_own = s.joint->n_own_coordinates(), m = s.active.size();
      for (const unsigned int b : s.body_index) add_range(e.rows, bodies[b].q, bodies[b].body->n_q());
      add_range(e.rows, s.own_q, n_own);
      e.columns = e.rows; // q entries
      for (const unsigned int b : s.body_index) add_range(e.rows, v0 + bodies[b].v, bodies[b].body->n_v());
      add_range(e.rows, v0 + s.own_v, n_own);
      for (unsigned int r = e.columns.size(); r < e.rows.size(); ++r) e.columns.push_back(e.rows[r]); // v entries
      add_range(e.rows, l0 + s.multiplier, m);
      add_range(e.rows, m0 + s.multiplier, m);
    }
  force_elements.assign(forces.size(), {});
  for (unsigned int f = 0; f < forces.size(); ++f)
    {
      ElementIndices &e = force_elements[f];
      for (const unsigned int b : forces[f].body_index) add_range(e.rows, v0 + bodies[b].v, bodies[b].body->n_v());
      for (const unsigned int b : forces[f].body_index) add_range(e.columns, bodies[b].q, bodies[b].body->n_q());
      for (const unsigned int b : forces[f].body_index) add_range(e.columns, v0 + bodies[b].v, bodies[b].body->n_v());
    }
}

std::string System::component_name(const unsigned int i) const
{
  const unsigned int v0 = nq, l0 = nq + nv, m0 = nq + nv + nlambda;
  for (const auto &b : bodies)
    {
      if (i >= b.q && i < b.q + b.body->n_q()) return "body " + b.body->name() + ", " + b.body->q_name(i - b.q);
      if (i >= v0 + b.v && i < v0 + b.v + b.body->n_v()) return "body " + b.body->name() + ", " + b.body->v_name(i - v0 - b.v);
      if (!b.body->is_ground() && i == m0 + b.normalisation) return "body " + b.body->name() + ", |p|^2 - 1";
    }
  for (const auto &j : joints)
    {
      const unsigned int n_own = j.joint->n_own_coordinates();
      if (i >= j.own_q && i < j.own_q + n_own) return "joint " + j.joint->name() + ", own coordinate " + std::to_string(i - j.own_q);
      if (i >= v0 + j.own_v && i < v0 + j.own_v + n_own) return "joint " + j.joint->name() + ", own velocity " + std::to_string(i - v0 - j.own_v);
      for (unsigned int r = 0; r < j.active.size(); ++r)
        {
          const std::string eq = j.joint->equation_name(j.active[r]);
          if (i == l0 + j.multiplier + r) return "joint " + j.joint->name() + ", velocity constraint: " + eq;
          if (i == m0 + j.multiplier + r) return "joint " + j.joint->name() + ", position constraint: " + eq;
        }
    }
  return "component " + std::to_string(i);
}

void System::initial_guess(Vector<double> &y) const
{
  y.reinit(size());
  for (const auto &b : bodies)
    if (!b.body->is_ground()) b.body->initial_coordinates((y.begin() + (b.q)), (y.begin() + (nq + b.v)));
  for (const auto &j : joints)
    if (j.joint->n_own_coordinates()) j.joint->initial_own_coordinates((y.begin() + (j.own_q)), (y.begin() + (nq + j.own_v)));
}

void System::differential_components(Vector<double> &id) const
{
  id.reinit(size());
  for (unsigned int i = 0; i < nq + nv; ++i) id[i] = 1;
  for (const auto &j : joints) // own velocities carry no mass: v' does not appear
    for (unsigned int k = 0; k < j.joint->n_own_coordinates(); ++k) id[nq + j.own_v + k] = 0;
}

std::vector<const double *> System::joint_q(const unsigned int j, const Vector<double> &y) const
{
  std::vector<const double *> q;
  for (const unsigned int b : joints[j].body_index) q.push_back(q_of(b, y));
  return q;
}

std::vector<const double *> System::force_q(const unsigned int f, const Vector<double> &y) const
{
  std::vector<const double *> q;
  for (const unsigned int b : forces[f].body_index) q.push_back(q_of(b, y));
  return q;
}

std::vector<const double *> System::force_v(const unsigned int f, const Vector<double> &y) const
{
  std::vector<const double *> v;
  for (const unsigned int b : forces[f].body_index) v.push_back(v_of(b, y));
  return v;
}

// ---------------------------------------------------------------------------------------------
// Element residuals

void System::body_residual(const unsigned int b, const double t, const Vector<double> &y, const Vector<double> &yp,
                           std::vector<double> &out) const
{
  (void)t;
  const BodySlot &s = bodies[b];
  const unsigned int n_q = s.body->n_q(), n_v = s.body->n_v();
  out.assign(n_q + n_v + 1, 0.0);
  const double *q = (y.begin() + (s.q)), *v = (y.begin() + (nq + s.v)), *vp = (yp.begin() + (nq + s.v));
  // F_q = q' - T v (+ 2 p mu_norm)
  s.body->coordinate_rates(q, v, out.data());
  for (unsigned int i = 0; i < n_q; ++i) out[i] = yp[s.q + i] - out[i];
  const double mu = y[nq + nv + nlambda + s.normalisation];
  for (unsigned int i = 0; i < 4; ++i) out[3 + i] += 2 * q[3 + i] * mu;
  // F_v = M v' - Q
  thread_local std::vector<double> Mvp, Q; // reused between calls: no heap allocation per body
  Mvp.resize(n_v);
  Q.resize(n_v);
  s.body->mass_times(q, vp, Mvp.data());
  s.body->forces(q, v, g, Q.data(), vp);
  for (unsigned int i = 0; i < n_v; ++i) out[n_q + i] = Mvp[i] - Q[i];
  out[n_q + n_v] = q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6] - 1;
}

void System::joint_position_jacobian(const unsigned int j, const Vector<double> &y, const JointEvaluation &e,
                                     FullMatrix<double> &Phi_q) const
{
  // Phi_q = B T^+: R and eta columns are B's; p columns 2 B_omega G(p) / |p|^2.
  const JointSlot &s = joints[j];
  const unsigned int n_own = s.joint->n_own_coordinates();
  unsigned int n_cols = n_own;
  for (const unsigned int b : s.body_index) n_cols += bodies[b].body->n_q();
  Phi_q.reinit(s.active.size(), n_cols);
  unsigned int col = 0;
  for (unsigned int m = 0; m < s.body_index.size(); ++m)
    {
      const BodySlot &bs = bodies[s.body_index[m]];
      if (bs.body->is_ground()) continue;
      const double *q = (y.begin() + (bs.q));
      const auto G = geometry::body_velocity_matrix({{q[3], q[4], q[5], q[6]}});
      const double p2 = q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6];
      for (unsigned int r = 0; r < s.active.size(); ++r)
        {
          const unsigned int k = s.active[r];
          for (unsigned int a = 0; a < 3; ++a) Phi_q(r, col + a) = e.B[m](k, a);
          for (unsigned int i = 0; i < 4; ++i)
            Phi_q(r, col + 3 + i) = 2 / p2 * (e.B[m](k, 3) * G[0][i] + e.B[m](k, 4) * G[1][i] + e.B[m](k, 5) * G[2][i]);
          for (unsigned int i = 0; i < bs.body->n_modes(); ++i) Phi_q(r, col + 7 + i) = e.B[m](k, 6 + i);
        }
      col += bs.body->n_q();
    }
  for (unsigned int r = 0; r < s.active.size(); ++r)
    for (unsigned int i = 0; i < n_own; ++i) Phi_q(r, col + i) = e.B_own(s.active[r], i);
}

void System::joint_residual(const unsigned int j, const double t, const Vector<double> &y, const Vector<double> &yp,
                            std::vector<double> &out) const
{
  const JointSlot &s = joints[j];
  const unsigned int n_own = s.joint->n_own_coordinates(), m = s.active.size(), n = s.joint->n_equations();
  const ElementIndices &ind = joint_elements[j];
  unsigned int n_q_cols = n_own, n_v_cols = n_own;
  for (const unsigned int b : s.body_index) n_q_cols += bodies[b].body->n_q(), n_v_cols += bodies[b].body->n_v();
  out.assign(ind.rows.size(), 0.0);
  // Reused between calls, one per joint (as GenericJoint's workspace): shared by the joints,
  // each would resize the others' storage.
  thread_local std::vector<JointResidualTerms> all_terms;
  thread_local std::vector<double> lambda, mu; // all n equations, the dropped ones zero
  thread_local std::vector<const double *> v;
  if (all_terms.size() <= j) all_terms.resize(j + 1);
  JointResidualTerms &terms = all_terms[j];
  lambda.assign(n, 0.0);
  mu.assign(n, 0.0);
  for (unsigned int r = 0; r < m; ++r)
    {
      lambda[s.active[r]] = y[nq + nv + s.multiplier + r];
      mu[s.active[r]] = y[nq + nv + nlambda + s.multiplier + r];
    }
  v.clear();
  for (const unsigned int b : s.body_index) v.push_back(v_of(b, y));
  s.joint->residual_terms(joint_q(j, y), n_own ? (y.begin() + s.own_q) : nullptr, t, v,
                          n_own ? (y.begin() + (nq + s.own_v)) : nullptr, lambda.data(), mu.data(), terms);
  // Phi_q^T mu = T^+T B^T mu (Phi_q = B T^+): the R and eta entries are B^T mu's, the p entries
  // 2 G(p)^T (B_omega^T mu) / |p|^2.
  const std::vector<double> &force_mu = terms.force_mu;
  unsigned int q_col = 0, v_col = 0;
  for (const unsigned int b : s.body_index)
    {
      const BodySlot &bs = bodies[b];
      if (bs.body->is_ground()) continue;
      const double *q = (y.begin() + (bs.q));
      const auto G = geometry::body_velocity_matrix({{q[3], q[4], q[5], q[6]}});
      const double p2 = q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6];
      for (unsigned int a = 0; a < 3; ++a) out[q_col + a] += force_mu[v_col + a];
      for (unsigned int i = 0; i < 4; ++i)
        out[q_col + 3 + i] +=
          2 / p2 * (force_mu[v_col + 3] * G[0][i] + force_mu[v_col + 4] * G[1][i] + force_mu[v_col + 5] * G[2][i]);
      for (unsigned int i = 0; i < bs.body->n_modes(); ++i) out[q_col + 7 + i] += force_mu[v_col + 6 + i];
      q_col += bs.body->n_q();
      v_col += bs.body->n_v();
    }
  for (unsigned int i = 0; i < n_own; ++i) out[q_col + i] += force_mu[v_col + i];
  for (unsigned int i = 0; i < n_own; ++i) out[n_q_cols - n_own + i] += yp[s.own_q + i] - y[nq + s.own_v + i];
  if (n_own) // - Q_own in the own velocity rows
    {
      std::vector<double> applied, dissipative;
      own_forces(j, t, y, applied, dissipative);
      for (unsigned int i = 0; i < n_own; ++i) out[n_q_cols + n_v_cols - n_own + i] -= applied[i] + dissipative[i];
    }
  // B^T lambda into the v rows, B v + Phi_t, Phi
  for (unsigned int c = 0; c < n_v_cols; ++c) out[n_q_cols + c] += terms.force_lambda[c];
  for (unsigned int r = 0; r < m; ++r)
    {
      out[n_q_cols + n_v_cols + r] = terms.rate[s.active[r]];
      out[n_q_cols + n_v_cols + m + r] = terms.phi[s.active[r]];
    }
  for (unsigned int i = 0; i < n_own; ++i) // held at an end stop: v = 0 instead of the force balance
    if (velocity_held(s.own_v + i)) out[n_q_cols + n_v_cols - n_own + i] = y[nq + s.own_v + i];
}

void System::force_residual(const unsigned int f, const double t, const Vector<double> &y, std::vector<double> &out) const
{
  const ElementIndices &ind = force_elements[f];
  std::vector<double> Q(ind.rows.size(), 0.0);
  std::vector<double *> Qb;
  unsigned int offset = 0;
  for (const unsigned int b : forces[f].body_index)
    {
      Qb.push_back(Q.data() + offset);
      offset += bodies[b].body->n_v();
    }
  forces[f].force->add_forces(force_q(f, y), force_v(f, y), t, Qb);
  out.resize(Q.size());
  for (unsigned int i = 0; i < Q.size(); ++i) out[i] = -Q[i];
}

void System::residual(const double t, const Vector<double> &y, const Vector<double> &yp, Vector<double> &F) const
{
  F.reinit(size());
  std::vector<double> out;
  auto scatter = [&](const ElementIndices &e) {
    for (unsigned int i = 0; i < e.rows.size(); ++i) F[e.rows[i]] += out[i];
  };
  for (unsigned int b = 1; b < bodies.size(); ++b)
    {
      body_residual(b, t, y, yp, out);
      scatter(body_elements[b]);
    }
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      joint_residual(j, t, y, yp, out);
      scatter(joint_elements[j]);
    }
  for (unsigned int f = 0; f < forces.size(); ++f)
    {
      force_residual(f, t, y, out);
      scatter(force_elements[f]);
    }
}
} // namespace flextrack::multibody
