// The Jacobian dF/dy + alpha dF/dy' of the GGL residual (system.h), element by element:
//  - bodies, analytic and exact (Body::equation_jacobians, body_jacobian.cc): the kinematic rows
//    q' - T(q) v + 2 p mu, the equations of motion M(q) v' - Q(q, v, v') - with their
//    derivatives in q, v and v' (geometric stiffening depends on the frame accelerations) - and
//    the normalisation |p|^2 - 1;
//  - joints: alpha on the joints' own q', Phi_q^T on mu, B^T on lambda and Phi_q in the
//    position-constraint rows, and the derivatives of Phi_q^T mu, B^T lambda and B v + Phi_t in
//    the positions (Joint::derivatives, analytic_joint_block): closed forms for markers fixed on
//    bodies or at interfaces, central differences of a track contact's marker alone for its own
//    second derivatives; a contact's own forces (drive, friction) by differences of those scalars;
//  - forces: dQ/dq and dQ/dv analytic (Force::derivatives, analytic_force_block);
//  - an element without analytic derivatives (two markers on one body) by central differences of
//    its residual w.r.t. the entries it reads, step h = 1e-6 (1 + |y_c|): truncation O(h^2 y''')
//    and rounding O(eps / h), both near 1e-10 relative.
#include <multibody/jacobian_solver.h>
#include <multibody/system.h>

#include <algorithm>

#include <Epetra_CrsMatrix.h>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
constexpr double relative_step = 1e-6;

enum ElementKind : unsigned int { body_element = 0, joint_element = 1, force_element = 2 };
} // namespace

const Epetra_CrsMatrix &System::jacobian() const
{
  Assert(solver, ExcMessage("assemble_jacobian() first"));
  return solver->matrix();
}

void System::add_local(const std::vector<unsigned int> &rows, const std::vector<unsigned int> &cols,
                       const FullMatrix<double> &block)
{
  AssertDimension(block.m(), rows.size());
  AssertDimension(block.n(), cols.size());
  if (block.m() * block.n() > 0) solver->add(rows, cols, &block(0, 0)); // FullMatrix: row-major, contiguous
}

void System::element_differences(const unsigned int kind, const unsigned int index, const double t,
                                 const Vector<double> &y, const Vector<double> &yp)
{
  Assert(kind == joint_element || kind == force_element, ExcInternalError()); // bodies: body_jacobian
  const ElementIndices &e = kind == joint_element ? joint_elements[index] : force_elements[index];
  FullMatrix<double> block(e.rows.size(), e.columns.size());
  // Columns whose derivatives are known without differences (see below): skipped in the loop.
  std::vector<bool> analytic(e.columns.size(), false);
  if (kind == joint_element)
    {
      // The joint residual is linear in the bodies' velocities, which appear only in the
      // velocity-constraint rows B v: those columns are B itself. (The joint's own velocities
      // also enter its own forces, e.g. friction: they keep their differences.)
      const JointSlot &s = joints[index];
      const unsigned int n_own = s.joint->n_own_coordinates(), m = s.active.size();
      JointEvaluation ev;
      s.joint->evaluate(joint_q(index, y), n_own ? (y.begin() + (s.own_q)) : nullptr, t, ev);
      unsigned int n_q_cols = n_own, n_v_cols = n_own;
      for (const unsigned int b : s.body_index) n_q_cols += bodies[b].body->n_q(), n_v_cols += bodies[b].body->n_v();
      unsigned int c = n_q_cols;
      for (unsigned int b = 0; b < s.body_index.size(); ++b)
        for (unsigned int k = 0; k < ev.B[b].n(); ++k, ++c)
          {
            analytic[c] = true;
            for (unsigned int r = 0; r < m; ++r) block(n_q_cols + n_v_cols + r, c) = ev.B[b](s.active[r], k);
          }
    }
  auto evaluate = [&](const Vector<double> &yy, std::vector<double> &out) {
    if (kind == joint_element) joint_residual(index, t, yy, yp, out);
    else force_residual(index, t, yy, out);
  };
  Vector<double> yy(y);
  std::vector<double> plus, minus;
  for (unsigned int c = 0; c < e.columns.size(); ++c)
    {
      if (analytic[c]) continue;
      const unsigned int col = e.columns[c];
      // An element on two markers of one body lists that body's columns twice: the first
      // difference holds the whole derivative (the residual reads y[col] through both), so a
      // repeat stays zero (add_local sums the two into one entry).
      if (std::find(e.columns.begin(), e.columns.begin() + c, col) != e.columns.begin() + c) continue;
      const double h = relative_step * (1 + std::abs(y[col]));
      yy[col] = y[col] + h;
      evaluate(yy, plus);
      yy[col] = y[col] - h;
      evaluate(yy, minus);
      yy[col] = y[col];
      for (unsigned int r = 0; r < e.rows.size(); ++r) block(r, c) = (plus[r] - minus[r]) / (2 * h);
    }
  if (kind == joint_element) // position-constraint rows: analytic Phi_q instead (below)
    {
      const unsigned int m = joints[index].active.size();
      for (unsigned int r = e.rows.size() - m; r < e.rows.size(); ++r)
        for (unsigned int c = 0; c < e.columns.size(); ++c) block(r, c) = 0;
    }
  add_local(e.rows, e.columns, block);
}

bool System::analytic_joint_block(const unsigned int j, const double t, const Vector<double> &y,
                                  const JointEvaluation &ev)
{
  if (element_differences_only) return false;
  const JointSlot &s = joints[j];
  const ElementIndices &e = joint_elements[j];
  const unsigned int l0 = nq + nv, m0 = nq + nv + nlambda, m = s.active.size(), n_own = s.joint->n_own_coordinates();
  thread_local std::vector<double> lambda, mu;
  lambda.assign(s.joint->n_equations(), 0.0);
  mu.assign(s.joint->n_equations(), 0.0);
  for (unsigned int r = 0; r < m; ++r) // mu = 0 in the Newton matrix (use_newton_matrix)
    lambda[s.active[r]] = y[l0 + s.multiplier + r], mu[s.active[r]] = newton_matrix ? 0.0 : y[m0 + s.multiplier + r];
  std::vector<const double *> v;
  for (const unsigned int b : s.body_index) v.push_back(v_of(b, y));
  const std::vector<const double *> q = joint_q(j, y);
  const double *own_q = n_own ? y.begin() + s.own_q : nullptr, *own_v = n_own ? y.begin() + nq + s.own_v : nullptr;
  thread_local JointDerivatives d;
  if (!s.joint->derivatives(q, own_q, t, lambda.data(), mu.data(), v, own_v, d)) return false;

  // Rows: q (bodies, own), v (bodies, own), lambda, mu; columns: q, v (joint_elements), with
  // n_q and n_v counting the own coordinates. The derivatives' rows are v (bodies, own), their
  // columns q (bodies, own): the same order.
  unsigned int n_q = n_own, n_v = n_own;
  for (const unsigned int b : s.body_index) n_q += bodies[b].body->n_q(), n_v += bodies[b].body->n_v();
  FullMatrix<double> block(e.rows.size(), e.columns.size());
  unsigned int qo = 0, vo = 0;
  for (unsigned int k = 0; k < s.body_index.size(); ++k)
    {
      const Body &body = *bodies[s.body_index[k]].body;
      const unsigned int nq_b = body.n_q(), nv_b = body.n_v();
      if (nv_b == 0) continue; // the ground
      const double *x = q[k];
      const auto G = geometry::body_velocity_matrix({{x[3], x[4], x[5], x[6]}});
      const double p2 = x[3] * x[3] + x[4] * x[4] + x[5] * x[5] + x[6] * x[6];
      // q rows: Phi_q^T mu = T^+^T B^T mu (T^+: R, 2 G / |p|^2, eta), so d/dq = T^+^T d(B^T mu)/dq
      // and the derivative of T^+ itself at fixed f = B^T mu (its omega part: G is linear in p).
      for (unsigned int c = 0; c < n_q; ++c)
        {
          for (unsigned int a = 0; a < 3; ++a) block(qo + a, c) = d.mu_q(vo + a, c);
          for (unsigned int i = 0; i < 4; ++i)
            block(qo + 3 + i, c) =
              2 / p2 * (G[0][i] * d.mu_q(vo + 3, c) + G[1][i] * d.mu_q(vo + 4, c) + G[2][i] * d.mu_q(vo + 5, c));
          for (unsigned int i = 0; i < nq_b - 7; ++i) block(qo + 7 + i, c) = d.mu_q(vo + 6 + i, c);
          for (unsigned int i = 0; i < nv_b; ++i) block(n_q + vo + i, c) = d.lambda_q(vo + i, c); // B^T lambda
        }
      Vector3 f; // omega part of B^T mu
      for (unsigned int r = 0; r < m; ++r)
        for (unsigned int l = 0; l < 3; ++l) f[l] += ev.B[k](s.active[r], 3 + l) * mu[s.active[r]];
      for (unsigned int i = 0; i < 4; ++i)
        {
          geometry::EulerParameters unit{{0, 0, 0, 0}};
          unit[i] = 1;
          const auto G_i = geometry::body_velocity_matrix(unit);
          for (unsigned int r = 0; r < 4; ++r)
            block(qo + 3 + r, qo + 3 + i) += 2 / p2 * (G_i[0][r] * f[0] + G_i[1][r] * f[1] + G_i[2][r] * f[2]) -
                                             4 * x[3 + i] / (p2 * p2) * (G[0][r] * f[0] + G[1][r] * f[1] + G[2][r] * f[2]);
        }
      qo += nq_b, vo += nv_b;
    }
  if (n_own)
    {
      // Own q rows: B_own^T mu + s' - v_s; own v rows: B_own^T lambda - Q_own(s, v_s, t), or
      // v_s = 0 where an end stop holds it. Q_own by central differences (a few scalars).
      std::vector<double> applied, dissipative;
      std::vector<std::vector<double>> dQ(2 * n_own); // d Q_own / d(own q, own v), per column
      Vector<double> yy(y);
      for (unsigned int c = 0; c < 2 * n_own; ++c)
        {
          const unsigned int col = c < n_own ? s.own_q + c : nq + s.own_v + c - n_own;
          const double h = 1e-6 * (1 + std::abs(y[col]));
          dQ[c].assign(n_own, 0.0);
          for (const double sign : {1.0, -1.0})
            {
              yy[col] = y[col] + sign * h;
              own_forces(j, t, yy, applied, dissipative);
              for (unsigned int i = 0; i < n_own; ++i) dQ[c][i] += sign * (applied[i] + dissipative[i]) / (2 * h);
            }
          yy[col] = y[col];
        }
      for (unsigned int i = 0; i < n_own; ++i)
        {
          const unsigned int q_row = n_q - n_own + i, v_row = n_q + n_v - n_own + i;
          for (unsigned int c = 0; c < n_q; ++c)
            {
              block(q_row, c) = d.mu_q(n_v - n_own + i, c);
              block(v_row, c) = d.lambda_q(n_v - n_own + i, c);
            }
          block(q_row, n_q + n_v - n_own + i) = -1; // - v_s
          for (unsigned int k = 0; k < n_own; ++k)
            {
              block(v_row, n_q - n_own + k) -= dQ[k][i];
              block(v_row, n_q + n_v - n_own + k) -= dQ[n_own + k][i];
            }
          if (velocity_held(s.own_v + i))
            {
              for (unsigned int c = 0; c < e.columns.size(); ++c) block(v_row, c) = 0;
              block(v_row, n_q + n_v - n_own + i) = 1;
            }
        }
    }
  // lambda rows: d(B v + Phi_t)/dq, and B, B_own in the v columns.
  for (unsigned int r = 0; r < m; ++r)
    {
      for (unsigned int c = 0; c < n_q; ++c) block(n_q + n_v + r, c) = d.rate_q(s.active[r], c);
      unsigned int c = n_q;
      for (unsigned int k = 0; k <= s.body_index.size(); ++k)
        {
          const FullMatrix<double> &B = k == s.body_index.size() ? ev.B_own : ev.B[k];
          for (unsigned int i = 0; i < B.n(); ++i, ++c) block(n_q + n_v + r, c) = B(s.active[r], i);
        }
    }
  add_local(e.rows, e.columns, block);
  return true;
}

bool System::analytic_force_block(const unsigned int f, const double t, const Vector<double> &y)
{
  if (element_differences_only) return false;
  thread_local FullMatrix<double> dQ_dq, dQ_dv;
  if (!forces[f].force->derivatives(force_q(f, y), force_v(f, y), t, dQ_dq, dQ_dv)) return false;
  // Rows: the bodies' v; columns: their q, then their v. The residual is -Q.
  const ElementIndices &e = force_elements[f];
  FullMatrix<double> block(e.rows.size(), e.columns.size());
  for (unsigned int r = 0; r < e.rows.size(); ++r)
    {
      for (unsigned int c = 0; c < dQ_dq.n(); ++c) block(r, c) = -dQ_dq(r, c);
      for (unsigned int c = 0; c < dQ_dv.n(); ++c) block(r, dQ_dq.n() + c) = -dQ_dv(r, c);
    }
  add_local(e.rows, e.columns, block);
  return true;
}

void System::body_jacobian(const unsigned int b, const double alpha, const Vector<double> &y, const Vector<double> &yp)
{
  const BodySlot &s = bodies[b];
  const unsigned int n_q = s.body->n_q(), n_v = s.body->n_v(), m0 = nq + nv + nlambda;
  const double *q = (y.begin() + (s.q)), *v = (y.begin() + (nq + s.v)), *vp = (yp.begin() + (nq + s.v));
  const double mu = y[m0 + s.normalisation];
  // Kinematic rows q' - T(q) v + 2 p mu: alpha on q'; -1 on R', omega -> p' = G(p)^T omega / 2
  // (G linear in p: its derivative is G of the unit vectors), eta'; 2 mu on p.
  for (unsigned int i = 0; i < n_q; ++i) add_derivative_term(s.q + i, s.q + i, alpha, 1.0);
  for (unsigned int a = 0; a < 3; ++a) solver->add(s.q + a, nq + s.v + a, -1);
  for (unsigned int k = 0; k < n_q - 7; ++k) solver->add(s.q + 7 + k, nq + s.v + 6 + k, -1);
  const auto G = geometry::body_velocity_matrix({{q[3], q[4], q[5], q[6]}});
  for (unsigned int i = 0; i < 4; ++i)
    {
      for (unsigned int l = 0; l < 3; ++l) solver->add(s.q + 3 + i, nq + s.v + 3 + l, -0.5 * G[l][i]);
      geometry::EulerParameters unit{{0, 0, 0, 0}};
      unit[i] = 1;
      const auto G_i = geometry::body_velocity_matrix(unit);
      for (unsigned int r = 0; r < 4; ++r)
        solver->add(s.q + 3 + r, s.q + 3 + i,
                    -0.5 * (G_i[0][r] * v[3] + G_i[1][r] * v[4] + G_i[2][r] * v[5]) + (r == i ? 2 * mu : 0.0));
      solver->add(s.q + 3 + i, m0 + s.normalisation, 2 * q[3 + i]); // the multiplier's column
      solver->add(m0 + s.normalisation, s.q + 3 + i, 2 * q[3 + i]); // |p|^2 - 1
    }
  // Equations of motion: dF/dq, dF/dv + alpha dF/dv'.
  FullMatrix<double> dq, dv, dvp;
  s.body->equation_jacobians(q, v, vp, g, dq, dv, dvp);
  std::vector<unsigned int> v_rows(n_v), q_cols(n_q);
  for (unsigned int i = 0; i < n_v; ++i) v_rows[i] = nq + s.v + i;
  for (unsigned int i = 0; i < n_q; ++i) q_cols[i] = s.q + i;
  if (derivative_terms)
    for (unsigned int i = 0; i < n_v; ++i)
      for (unsigned int k = 0; k < n_v; ++k) add_derivative_term(v_rows[i], v_rows[k], alpha, dvp(i, k));
  else
    dv.add(alpha, dvp);
  add_local(v_rows, q_cols, dq);
  add_local(v_rows, v_rows, dv);
}

std::vector<std::vector<int>> System::jacobian_pattern() const
{
  const unsigned int l0 = nq + nv, m0 = nq + nv + nlambda;
  // Vectors sorted at the end, not sets: a full-FE body's pattern holds millions of entries.
  std::vector<std::vector<int>> pattern(size());
  auto add = [&](const std::vector<unsigned int> &rows, const std::vector<unsigned int> &cols) {
    for (const unsigned int r : rows) pattern[r].insert(pattern[r].end(), cols.begin(), cols.end());
  };
  for (unsigned int b = 1; b < bodies.size(); ++b)
    {
      add(body_elements[b].rows, body_elements[b].columns);
      add(body_elements[b].rows, {m0 + bodies[b].normalisation});
    }
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      std::vector<unsigned int> multipliers;
      for (unsigned int r = 0; r < joints[j].active.size(); ++r)
        multipliers.insert(multipliers.end(), {l0 + joints[j].multiplier + r, m0 + joints[j].multiplier + r});
      add(joint_elements[j].rows, joint_elements[j].columns);
      add(joint_elements[j].rows, multipliers);
    }
  for (unsigned int f = 0; f < forces.size(); ++f) add(force_elements[f].rows, force_elements[f].columns);
  for (unsigned int i = 0; i < size(); ++i)
    {
      std::vector<int> &row = pattern[i];
      row.push_back(i); // the diagonal, also for unused multipliers
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
    }
  return pattern;
}

void System::assemble_jacobian(const double t, const double alpha, const Vector<double> &y, const Vector<double> &yp)
{
  const unsigned int l0 = nq + nv, m0 = nq + nv + nlambda;
  if (!solver)
    {
      const auto pattern = jacobian_pattern();
      solver = std::make_unique<JacobianSolver>(pattern, dense_factorisation_is_faster(*this, pattern), nq);
    }
  ++jacobian_count;
  solver->zero();
  for (unsigned int b = 1; b < bodies.size(); ++b) body_jacobian(b, alpha, y, yp);
  for (unsigned int j = 0; j < joints.size(); ++j)
    {
      const JointSlot &s = joints[j];
      const ElementIndices &e = joint_elements[j];
      const unsigned int m = s.active.size(), n_own = s.joint->n_own_coordinates();
      JointEvaluation ev; // at (t, y): B for the analytic block and for the terms below
      s.joint->evaluate(joint_q(j, y), n_own ? (y.begin() + (s.own_q)) : nullptr, t, ev);
      if (!analytic_joint_block(j, t, y, ev)) element_differences(joint_element, j, t, y, yp);
      FullMatrix<double> Phi_q;
      joint_position_jacobian(j, y, ev, Phi_q);
      const unsigned int n_qc = Phi_q.n(), n_vc = e.columns.size() - n_qc;
      for (unsigned int i = 0; i < n_own; ++i) add_derivative_term(s.own_q + i, s.own_q + i, alpha, 1.0);
      for (unsigned int r = 0; r < m; ++r)
        {
          for (unsigned int c = 0; c < n_qc; ++c)
            {
              solver->add(e.columns[c], m0 + s.multiplier + r, Phi_q(r, c)); // Phi_q^T mu
              solver->add(m0 + s.multiplier + r, e.columns[c], Phi_q(r, c)); // Phi
            }
          unsigned int c = 0;
          for (unsigned int b = 0; b <= s.body_index.size(); ++b)
            {
              const FullMatrix<double> &B = b == s.body_index.size() ? ev.B_own : ev.B[b];
              for (unsigned int k = 0; k < B.n(); ++k, ++c)
                if (!(b == s.body_index.size() && velocity_held(s.own_v + k))) // a held row has no B^T lambda
                  solver->add(e.columns[n_qc + c], l0 + s.multiplier + r, B(s.active[r], k)); // B^T lambda
            }
          Assert(c == n_vc, ExcInternalError());
          (void)n_vc;
        }
    }
  for (unsigned int f = 0; f < forces.size(); ++f)
    if (!analytic_force_block(f, t, y)) element_differences(force_element, f, t, y, yp);
}

void System::add_derivative_term(const unsigned int row, const unsigned int col, const double alpha, const double value)
{
  if (derivative_terms)
    (*derivative_terms)[std::size_t(col) * size() + row] += value;
  else
    solver->add(row, col, alpha * value);
}

void System::assemble_jacobian_parts(const double t, const Vector<double> &y, const Vector<double> &yp,
                                     std::vector<double> &dF_dyp)
{
  dF_dyp.assign(std::size_t(size()) * size(), 0.0);
  struct Redirect // the y' terms go to dF_dyp for this assembly only, also if it throws
  {
    std::vector<double> *&target;
    ~Redirect() { target = nullptr; }
  } redirect{derivative_terms};
  derivative_terms = &dF_dyp;
  assemble_jacobian(t, 0.0, y, yp);
}

bool System::factorize(const bool fresh_pivots)
{
  Assert(solver, ExcMessage("assemble_jacobian() first"));
  return solver->factorize(fresh_pivots);
}

unsigned long System::n_condensed_factorizations() const { return solver ? solver->n_condensed_factorizations() : 0; }

unsigned int System::condensed_size() const { return solver ? solver->condensed_size() : 0; }

void System::solve(const double *b, double *x)
{
  solver->solve(b, x);
}
} // namespace flextrack::multibody
