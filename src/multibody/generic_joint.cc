// The generic joint: constraint rows, their gradients w.r.t. the markers' positions and axes,
// and the chain rule through the marker Jacobians (see generic_joint.h).
#include <base/input_error.h>
#include <multibody/generic_joint.h>
#include <multibody/lapack.h>

#include <algorithm>
#include <array>
#include <atomic>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
const char *axis_name[] = {"x", "y", "z"};
std::atomic<unsigned long long> next_workspace_id{1};
} // namespace

GenericJoint::Local &GenericJoint::workspace() const
{
  struct Slot
  {
    unsigned long long owner = 0;
    Local local;
  };
  thread_local std::array<Slot, 16> slots;
  thread_local unsigned int next = 0;
  for (Slot &slot : slots)
    if (slot.owner == id) return slot.local;
  Slot &slot = slots[next++ % slots.size()];
  slot.owner = id;
  return slot.local;
}

GenericJoint::GenericJoint(std::string name, std::unique_ptr<Marker> follower, std::unique_ptr<Marker> base,
                           const JointMask &mask, const DriverKind driver_kind,
                           std::shared_ptr<const geometry::Expression> driver_law)
  : Joint(std::move(name)), driver(driver_kind), law(std::move(driver_law)), id(next_workspace_id++)
{
  markers[0] = std::move(follower);
  markers[1] = std::move(base);
  if (driver == DriverKind::angle && mask.rotation[2])
    throw InputError("Joint " + this->name() + "/Driver", "an angle driver needs the rotation about z to be free");
  if (driver == DriverKind::displacement && mask.translation[2])
    throw InputError("Joint " + this->name() + "/Driver", "a displacement driver needs the translation along z to be free");
  if (driver != DriverKind::none && !law) throw InputError("Joint " + this->name() + "/Driver", "needs an expression of t");
  if (driver == DriverKind::own_coordinate && markers[1]->n_own_coordinates() != 1)
    throw InputError("Joint " + this->name() + "/Driver", "only a joint on a track can drive the arc length");
  for (unsigned int a = 0; a < 3; ++a)
    if (mask.translation[a]) rows.push_back({RowKind::translation, a, 0, false, std::string("translation along ") + axis_name[a], nullptr});
  if (driver == DriverKind::displacement)
    rows.push_back({RowKind::translation, 2, 0, true, "driven displacement along z", nullptr});

  const unsigned int n_locked = mask.rotation[0] + mask.rotation[1] + mask.rotation[2];
  if (n_locked == 3)
    {
      rows.push_back({RowKind::rotation, 2, 0, false, "rotation about y (e1_z . e2_x)", nullptr});
      rows.push_back({RowKind::rotation, 2, 1, false, "rotation about x (e1_z . e2_y)", nullptr});
      rows.push_back({RowKind::rotation, 0, 1, false, "rotation about z (e1_x . e2_y)", nullptr});
    }
  else if (n_locked == 2)
    {
      const unsigned int c = !mask.rotation[0] ? 0 : !mask.rotation[1] ? 1 : 2, a = (c + 1) % 3, b = (c + 2) % 3;
      rows.push_back({RowKind::rotation, c, a, false,
                      std::string("rotation about ") + axis_name[b] + " (e1_" + axis_name[c] + " . e2_" + axis_name[a] + ")", nullptr});
      rows.push_back({RowKind::rotation, c, b, false,
                      std::string("rotation about ") + axis_name[a] + " (e1_" + axis_name[c] + " . e2_" + axis_name[b] + ")", nullptr});
    }
  else if (n_locked == 1)
    {
      const unsigned int c = mask.rotation[0] ? 0 : mask.rotation[1] ? 1 : 2, a = (c + 1) % 3, b = (c + 2) % 3;
      rows.push_back({RowKind::rotation, a, b, false,
                      std::string("rotation about ") + axis_name[c] + " (e1_" + axis_name[a] + " . e2_" + axis_name[b] + ")", nullptr});
    }
  if (driver == DriverKind::angle) rows.push_back({RowKind::angle, 0, 0, false, "driven angle about z", nullptr});
  if (driver == DriverKind::own_coordinate) add_own_driver(markers[0]->n_own_coordinates(), law, "driven arc length s");
}

void GenericJoint::add_own_driver(const unsigned int index, std::shared_ptr<const geometry::Expression> own_law,
                                  const std::string &row_name)
{
  Assert(index < n_own_coordinates() && own_law, ExcMessage("no such own coordinate, or no law"));
  rows.push_back({RowKind::own, index, 0, true, row_name, std::move(own_law)});
}

unsigned int GenericJoint::n_own_coordinates() const
{
  return markers[0]->n_own_coordinates() + markers[1]->n_own_coordinates();
}

void GenericJoint::initial_own_coordinates(double *q, double *v) const
{
  const unsigned int n0 = markers[0]->n_own_coordinates();
  if (n0) markers[0]->initial_own_coordinates(q, v);
  if (markers[1]->n_own_coordinates()) markers[1]->initial_own_coordinates(q + n0, v + n0);
}

const double *GenericJoint::own_of(const unsigned int m, const double *own_q) const
{
  if (!markers[m]->n_own_coordinates()) return nullptr;
  return own_q + (m == 0 ? 0 : markers[0]->n_own_coordinates());
}

namespace
{
/// Phi_t of the driven-angle row e_i,x . (-sin th e_j,x + cos th e_j,y) for the law's value and
/// rate @p s: -(e_i,x . (cos th e_j,x + sin th e_j,y)) th'.
double angle_rate(const Vector3 &ei_x, const Vector3 &ej_x, const Vector3 &ej_y, const geometry::Dual &s)
{
  const double c = std::cos(s.value()), sn = std::sin(s.value());
  return -(ei_x * (c * ej_x + sn * ej_y)) * s.derivative(1);
}
} // namespace

void GenericJoint::evaluate_rows(const std::vector<const double *> &q, const double *own_q, const double t, Local &l,
                                 Vector<double> &phi, Vector<double> &phi_t) const
{
  for (unsigned int m = 0; m < 2; ++m) markers[m]->evaluate(q[m], own_of(m, own_q), l.k[m]);
  const MarkerKinematics &ki = l.k[0], &kj = l.k[1];
  const Vector3 d = ki.position - kj.position;
  phi.reinit(rows.size());
  phi_t.reinit(rows.size());
  l.grad.assign(rows.size(), Gradient());
  geometry::Dual s; // a drive law's value and rate (Phi and Phi_t need no more)
  if (law) s = law->dual(t);
  for (unsigned int r = 0; r < rows.size(); ++r)
    {
      const Row &row = rows[r];
      Gradient &g = l.grad[r];
      switch (row.kind)
        {
          case RowKind::translation:
            phi[r] = kj.axes[row.a] * d - (row.driven ? s.value() : 0.0);
            phi_t[r] = row.driven ? -s.derivative(1) : 0.0;
            g[0] = kj.axes[row.a];
            g[4] = -kj.axes[row.a];
            g[5 + row.a] = d;
            break;
          case RowKind::rotation:
            phi[r] = ki.axes[row.a] * kj.axes[row.b];
            g[1 + row.a] = kj.axes[row.b];
            g[5 + row.b] = ki.axes[row.a];
            break;
          case RowKind::angle:
            {
              const double c = std::cos(s.value()), sn = std::sin(s.value());
              const Vector3 target = -sn * kj.axes[0] + c * kj.axes[1];
              phi[r] = ki.axes[0] * target;
              phi_t[r] = angle_rate(ki.axes[0], kj.axes[0], kj.axes[1], s);
              g[1] = target;
              g[5] = -sn * ki.axes[0];
              g[6] = c * ki.axes[0];
              break;
            }
          case RowKind::own: // s - s(t): no marker gradient; its B_own entry is set in evaluate()
            {
              const geometry::Dual s_d = row.own_law->dual(t);
              phi[r] = own_q[row.a] - s_d.value();
              phi_t[r] = -s_d.derivative(1);
              break;
            }
        }
    }
}

void GenericJoint::driver_rates(const std::vector<const double *> &q, const double *own_q, const double t,
                                Vector<double> &phi_t) const
{
  // The angle row's Phi_t needs both markers' axes (their Jacobians are not needed).
  const bool angle = std::any_of(rows.begin(), rows.end(), [](const Row &r) { return r.kind == RowKind::angle; });
  std::array<Vector3, 3> ei, ej;
  if (angle)
    {
      markers[0]->axes(q[0], own_of(0, own_q), ei);
      markers[1]->axes(q[1], own_of(1, own_q), ej);
    }
  phi_t.reinit(rows.size());
  for (unsigned int r = 0; r < rows.size(); ++r)
    {
      const Row &row = rows[r];
      if (row.kind == RowKind::translation && row.driven) phi_t[r] = -law->dual(t).derivative(1);
      else if (row.kind == RowKind::own) phi_t[r] = -row.own_law->dual(t).derivative(1);
      else if (row.kind == RowKind::angle) phi_t[r] = angle_rate(ei[0], ej[0], ej[1], law->dual(t));
    }
}

void GenericJoint::evaluate(const std::vector<const double *> &q, const double *own_q, const double t,
                            JointEvaluation &e) const
{
  // Reused between calls (the residual evaluates every joint several times per step): its
  // matrices keep their storage, which saves about 10 heap allocations per call. Nothing
  // evaluated from here evaluates a joint again, and each thread has its own.
  Local &l = workspace();
  evaluate_rows(q, own_q, t, l, e.phi, e.phi_t);
  e.B.resize(2);
  e.B_own.reinit(rows.size(), n_own_coordinates());
  unsigned int own_column = 0;
  for (unsigned int m = 0; m < 2; ++m)
    {
      // The marker's columns: its body's velocities, then its own coordinates (into B_own).
      const MarkerKinematics &k = l.k[m];
      const unsigned int nv = markers[m]->body().n_v(), n_own = markers[m]->n_own_coordinates();
      e.B[m].reinit(rows.size(), nv);
      for (unsigned int r = 0; r < rows.size(); ++r)
        {
          // A row depends on few of the marker's four vectors (a rotation row on one axis of
          // each marker, a translation row on no axis of the first): zero gradients are skipped,
          // the sums over the others are taken in the same order as before.
          const Gradient &g = l.grad[r];
          const auto nonzero = [](const Vector3 &w) { return w[0] != 0 || w[1] != 0 || w[2] != 0; };
          const bool position = nonzero(g[4 * m]);
          std::array<bool, 3> axis;
          for (unsigned int x = 0; x < 3; ++x) axis[x] = nonzero(g[4 * m + 1 + x]);
          for (unsigned int c = 0; c < nv + n_own; ++c)
            {
              double v = 0;
              for (unsigned int a = 0; a < 3; ++a)
                {
                  if (position) v += g[4 * m][a] * k.J_position(a, c);
                  for (unsigned int x = 0; x < 3; ++x)
                    if (axis[x]) v += g[4 * m + 1 + x][a] * k.J_axes[x](a, c);
                }
              (c < nv ? e.B[m](r, c) : e.B_own(r, own_column + c - nv)) = v;
            }
        }
      own_column += n_own;
    }
  for (unsigned int r = 0; r < rows.size(); ++r)
    if (rows[r].kind == RowKind::own) e.B_own(r, rows[r].a) = 1;
}

void GenericJoint::residual_terms(const std::vector<const double *> &q, const double *own_q, const double t,
                                  const std::vector<const double *> &v, const double *own_v, const double *lambda,
                                  const double *mu, JointResidualTerms &r) const
{
  Local &l = workspace();
  evaluate_rows(q, own_q, t, l, r.phi, r.rate); // rate = Phi_t so far
  const bool forces = lambda && mu;
  unsigned int n_columns = n_own_coordinates();
  for (const auto &marker : markers) n_columns += marker->body().n_v();
  r.force_lambda.assign(forces ? n_columns : 0, 0.0);
  r.force_mu.assign(forces ? n_columns : 0, 0.0);
  // The own coordinates' columns follow both bodies' velocities.
  const unsigned int first_own = markers[0]->body().n_v() + markers[1]->body().n_v();
  unsigned int body_column = 0, own_column = first_own;
  for (unsigned int m = 0; m < 2; ++m)
    {
      const MarkerKinematics &k = l.k[m];
      const unsigned int nv = markers[m]->body().n_v(), n_own = markers[m]->n_own_coordinates();
      const double *own_rate = n_own ? own_of(m, own_v) : nullptr;
      // The marker's four vectors (position, three axes): their Jacobians, their rates J x', and
      // the sums of the row gradients weighted by lambda and by mu.
      const FullMatrix<double> *J[4] = {&k.J_position, &k.J_axes[0], &k.J_axes[1], &k.J_axes[2]};
      std::array<Vector3, 4> rate, weight_lambda, weight_mu;
      for (unsigned int x = 0; x < 4; ++x)
        {
          // A vector no row depends on (the follower's axes in a translation row, ...) is skipped.
          if (std::none_of(l.grad.begin(), l.grad.end(), [&](const Gradient &g) {
                const Vector3 &w = g[4 * m + x];
                return w[0] != 0 || w[1] != 0 || w[2] != 0;
              }))
            continue;
          if (forces)
            for (unsigned int row = 0; row < rows.size(); ++row)
              {
                weight_lambda[x] += lambda[row] * l.grad[row][4 * m + x];
                weight_mu[x] += mu[row] * l.grad[row][4 * m + x];
              }
          for (unsigned int c = 0; c < nv + n_own; ++c)
            {
              const double x_rate = c < nv ? v[m][c] : own_rate[c - nv];
              const unsigned int column = c < nv ? body_column + c : own_column + c - nv;
              for (unsigned int a = 0; a < 3; ++a)
                {
                  const double Jac = (*J[x])(a, c);
                  rate[x][a] += Jac * x_rate;
                  if (forces)
                    {
                      r.force_lambda[column] += weight_lambda[x][a] * Jac;
                      r.force_mu[column] += weight_mu[x][a] * Jac;
                    }
                }
            }
        }
      for (unsigned int row = 0; row < rows.size(); ++row)
        for (unsigned int x = 0; x < 4; ++x) r.rate[row] += l.grad[row][4 * m + x] * rate[x];
      body_column += nv;
      own_column += n_own;
    }
  // A driven own coordinate's row: B_own = 1 in its column (evaluate), no marker gradient.
  for (unsigned int row = 0; row < rows.size(); ++row)
    if (rows[row].kind == RowKind::own)
      {
        r.rate[row] += own_v[rows[row].a];
        if (forces)
          {
            r.force_lambda[first_own + rows[row].a] += lambda[row];
            r.force_mu[first_own + rows[row].a] += mu[row];
          }
      }
}

void GenericJoint::reaction(const std::vector<const double *> &q, const double *own_q, const double t,
                            const double *lambda, Vector3 &force, Vector3 &torque) const
{
  std::array<Vector3, 3> unused;
  reaction(q, own_q, t, lambda, force, torque, unused);
}

void GenericJoint::reaction(const std::vector<const double *> &q, const double *own_q, const double t,
                            const double *lambda, Vector3 &force, Vector3 &torque, std::array<Vector3, 3> &base_axes) const
{
  // Generalised constraint force -B^T lambda = J_r^T F + J_w^T T at the follower marker, with
  // F = -sum lambda dPhi/dr_i and T = -sum lambda sum_a e_a x dPhi/de_a (e_a' = omega x e_a).
  Local l;
  Vector<double> phi, phi_t;
  evaluate_rows(q, own_q, t, l, phi, phi_t);
  force = torque = Vector3();
  for (unsigned int r = 0; r < rows.size(); ++r)
    {
      force -= lambda[r] * l.grad[r][0];
      for (unsigned int a = 0; a < 3; ++a) torque -= lambda[r] * cross_product_3d(l.k[0].axes[a], l.grad[r][1 + a]);
    }
  base_axes = l.k[1].axes;
}
} // namespace flextrack::multibody

namespace flextrack::multibody
{
void GenericJoint::row_hessian(const unsigned int r, const double angle, std::vector<HessianTerm> &terms) const
{
  terms.clear();
  const auto pair = [&](const unsigned int a, const unsigned int b, const double c) {
    terms.push_back({a, b, c});
    terms.push_back({b, a, c});
  };
  const Row &row = rows[r];
  switch (row.kind)
    {
      case RowKind::translation: // e_j,a . (r_i - r_j)
        pair(0, 5 + row.a, 1);
        pair(4, 5 + row.a, -1);
        break;
      case RowKind::rotation: // e_i,a . e_j,b
        pair(1 + row.a, 5 + row.b, 1);
        break;
      case RowKind::angle: // e_i,x . (-sin th e_j,x + cos th e_j,y)
        pair(1, 5, -std::sin(angle));
        pair(1, 6, std::cos(angle));
        break;
      case RowKind::own: // linear in the own coordinate
        break;
    }
}

bool GenericJoint::derivatives(const std::vector<const double *> &q, const double *own_q, const double t,
                               const double *lambda, const double *mu, const std::vector<const double *> &v,
                               const double *own_v, JointDerivatives &d) const
{
  // Per marker quantity y_a (a = 0..7: r_i, e_i[3], r_j, e_j[3]), with its Jacobian J_a (columns:
  // the body's v, then the marker's own coordinates), Y_a = dy_a/dq = J_a T^+ (T^+: R, the
  // omega columns times 2 G(p) / |p|^2, eta; own coordinates as they are), u_a = J_a v, and for
  // each row the quadratic form C of row_hessian():
  //   d(B^T w)/dq          = sum_ab W_ab J_a^T Y_b + sum_a H_a(w_a),   W = sum_r w_r C_r,
  //                          w_a = sum_r w_r dPhi_r/dy_a,  H_a(w) = d(J_a^T w)/dq at fixed w
  //   d(B_r v + Phi_t)/dq  = sum_ab C_r,ab u_a^T Y_b + sum_a (dPhi_r/dy_a)^T V_a  (+ Phi_t's own),
  //                          V_a = d(J_a v)/dq at fixed v.
  // H and V of a marker of body-fixed form in closed form (BodyFixedDerivatives, marker.h).
  // Of any other marker (a track contact) from central differences of its own J over its
  // body's q and its own coordinates: one marker evaluation per step, not a joint's.
  if (&markers[0]->body() == &markers[1]->body()) return false;

  Local &l = workspace();
  thread_local Vector<double> phi, phi_t;
  evaluate_rows(q, own_q, t, l, phi, phi_t);
  double angle = 0, angle_rate = 0;
  if (driver == DriverKind::angle)
    {
      const geometry::Dual s = law->dual(t);
      angle = s.value(), angle_rate = s.derivative(1);
    }

  struct Side
  {
    unsigned int nq = 0, nv = 0, n_own = 0, q0 = 0, v0 = 0, own0 = 0;
    const BodyFixedForm *form = nullptr;
    BodyFixedDerivatives fixed; // its V and H (a marker of body-fixed form on a moving body)
    std::vector<double> v;      // the body's velocities, then the marker's own
    std::array<const FullMatrix<double> *, 4> J;
    std::array<Vector3, 4> u;
    std::array<FullMatrix<double>, 4> Y, V;
  };
  thread_local Side side[2];
  unsigned int nq_total = 0, nv_total = 0;
  for (unsigned int m = 0; m < 2; ++m)
    {
      Side &S = side[m];
      const Body &body = markers[m]->body();
      S.nq = body.n_q(), S.nv = body.n_v(), S.n_own = markers[m]->n_own_coordinates();
      S.q0 = nq_total, S.v0 = nv_total, S.own0 = m == 0 ? 0 : side[0].n_own;
      S.form = markers[m]->body_fixed_form();
      nq_total += S.nq, nv_total += S.nv;
    }
  const unsigned int n_own = side[0].n_own + side[1].n_own;
  // w_a = sum_r w_r dPhi_r/dy_a for both multipliers: H_a(w_a) of a marker without closed forms
  // is summed column by column while its J is differenced (nothing of size n_q x n_v is kept).
  std::array<Vector3, 8> w_lambda, w_mu;
  for (unsigned int r = 0; r < rows.size(); ++r)
    for (unsigned int a = 0; a < 8; ++a) w_lambda[a] += lambda[r] * l.grad[r][a], w_mu[a] += mu[r] * l.grad[r][a];
  d.lambda_q.reinit(nv_total + n_own, nq_total + n_own);
  d.mu_q.reinit(nv_total + n_own, nq_total + n_own);
  const auto q_column = [&](const Side &S, const unsigned int k) { return k < S.nq ? S.q0 + k : nq_total + S.own0 + k - S.nq; };
  const auto v_row = [&](const Side &S, const unsigned int i) { return i < S.nv ? S.v0 + i : nv_total + S.own0 + i - S.nv; };

  for (unsigned int m = 0; m < 2; ++m)
    {
      Side &S = side[m];
      const MarkerKinematics &k = l.k[m];
      S.v.assign(S.nv + S.n_own, 0.0);
      for (unsigned int i = 0; i < S.nv; ++i) S.v[i] = v[m][i];
      for (unsigned int i = 0; i < S.n_own; ++i) S.v[S.nv + i] = own_v[S.own0 + i];
      double c2 = 0; // 2 / |p|^2 and G(p): Y = J T^+
      std::array<std::array<double, 4>, 3> G{};
      if (S.nv > 0)
        {
          c2 = 2 / (q[m][3] * q[m][3] + q[m][4] * q[m][4] + q[m][5] * q[m][5] + q[m][6] * q[m][6]);
          G = geometry::body_velocity_matrix({{q[m][3], q[m][4], q[m][5], q[m][6]}});
        }
      for (unsigned int a = 0; a < 4; ++a)
        {
          const FullMatrix<double> &J = *(S.J[a] = a == 0 ? &k.J_position : &k.J_axes[a - 1]);
          S.u[a] = Vector3();
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int c = 0; c < S.nv + S.n_own; ++c) S.u[a][i] += J(i, c) * S.v[c];
          FullMatrix<double> &Y = S.Y[a];
          Y.reinit(3, S.nq + S.n_own);
          for (unsigned int i = 0; i < 3; ++i)
            {
              if (S.nv > 0)
                {
                  if (a == 0) Y(i, i) = 1;
                  for (unsigned int e = 0; e < 4; ++e)
                    Y(i, 3 + e) = c2 * (J(i, 3) * G[0][e] + J(i, 4) * G[1][e] + J(i, 5) * G[2][e]);
                  for (unsigned int j = 7; j < S.nq; ++j) Y(i, j) = J(i, j - 1);
                }
              for (unsigned int j = 0; j < S.n_own; ++j) Y(i, S.nq + j) = J(i, S.nv + j);
            }
        }
      if (S.form) // closed forms; such a marker has no own coordinates
        {
          if (S.nv == 0) // the ground: nothing moves
            {
              for (auto &V : S.V) V.reinit(3, 0);
              continue;
            }
          S.fixed.reinit(*S.form, markers[m]->body(), q[m], v[m], k);
          for (unsigned int a = 0; a < 4; ++a) S.V[a] = S.fixed.V(a);
          continue;
        }
      // Central differences of the marker's J over its body's q and its own coordinates.
      thread_local std::vector<double> x, own;
      thread_local MarkerKinematics plus, minus;
      x.assign(S.nq, 0.0);
      own.assign(S.n_own, 0.0);
      for (unsigned int i = 0; i < S.nq; ++i) x[i] = q[m][i];
      for (unsigned int i = 0; i < S.n_own; ++i) own[i] = own_q[S.own0 + i];
      for (unsigned int a = 0; a < 4; ++a) S.V[a].reinit(3, S.nq + S.n_own);
      thread_local FullMatrix<double> dJ;
      dJ.reinit(3, S.nv + S.n_own); // every entry is written below
      // A track contact's J does not depend on R, and on eta only through a few columns, in
      // closed form: only its Euler-parameter and own columns are differenced (10 marker
      // evaluations instead of 2 (7 + n + 1) on a body of n modes).
      thread_local std::vector<ModalJacobianDerivative> modal;
      const bool closed_modal = S.n_own == 1 && markers[m]->modal_jacobian_derivatives(q[m], own.data(), modal);
      for (unsigned int c = 0; c < S.nq + S.n_own; ++c)
        {
          if (closed_modal && c < 3) continue; // dJ/dR = 0: nothing to add
          if (closed_modal && c >= 7 && c < S.nq)
            {
              const ModalJacobianDerivative &dm = modal[c - 7];
              const unsigned int s_col = S.nv; // the own coordinate's column of J
              for (unsigned int a = 0; a < 4; ++a)
                {
                  const Vector3 &wl = w_lambda[4 * m + a], &wm = w_mu[4 * m + a];
                  for (unsigned int i = 0; i < 3; ++i)
                    {
                      double Vi = dm.own[a][i] * S.v[s_col];
                      for (unsigned int b = 0; b < 3; ++b) Vi += dm.omega[a][i][b] * S.v[3 + b];
                      S.V[a](i, c) += Vi;
                    }
                  // H_a(w_a), column c: dJ_a^T w_a, nonzero in the omega rows and the s row
                  for (unsigned int b = 0; b < 3; ++b)
                    {
                      d.lambda_q(v_row(S, 3 + b), q_column(S, c)) +=
                        dm.omega[a][0][b] * wl[0] + dm.omega[a][1][b] * wl[1] + dm.omega[a][2][b] * wl[2];
                      d.mu_q(v_row(S, 3 + b), q_column(S, c)) +=
                        dm.omega[a][0][b] * wm[0] + dm.omega[a][1][b] * wm[1] + dm.omega[a][2][b] * wm[2];
                    }
                  d.lambda_q(v_row(S, s_col), q_column(S, c)) += dm.own[a] * wl;
                  d.mu_q(v_row(S, s_col), q_column(S, c)) += dm.own[a] * wm;
                }
              continue;
            }
          double &entry = c < S.nq ? x[c] : own[c - S.nq];
          const double x0 = entry, h = 1e-6 * (1 + std::abs(x0));
          entry = x0 + h;
          markers[m]->evaluate(S.nq ? x.data() : nullptr, own.data(), plus);
          entry = x0 - h;
          markers[m]->evaluate(S.nq ? x.data() : nullptr, own.data(), minus);
          entry = x0;
          for (unsigned int a = 0; a < 4; ++a)
            {
              const FullMatrix<double> &Jp = a == 0 ? plus.J_position : plus.J_axes[a - 1];
              const FullMatrix<double> &Jm = a == 0 ? minus.J_position : minus.J_axes[a - 1];
              for (unsigned int i = 0; i < 3; ++i)
                for (unsigned int j = 0; j < S.nv + S.n_own; ++j)
                  {
                    dJ(i, j) = (Jp(i, j) - Jm(i, j)) / (2 * h);
                    S.V[a](i, c) += dJ(i, j) * S.v[j];
                  }
              // H_a(w_a), column c: dJ_a^T w_a
              const Vector3 &wl = w_lambda[4 * m + a], &wm = w_mu[4 * m + a];
              for (unsigned int i = 0; i < S.nv + S.n_own; ++i)
                {
                  d.lambda_q(v_row(S, i), q_column(S, c)) += dJ(0, i) * wl[0] + dJ(1, i) * wl[1] + dJ(2, i) * wl[2];
                  d.mu_q(v_row(S, i), q_column(S, c)) += dJ(0, i) * wm[0] + dJ(1, i) * wm[1] + dJ(2, i) * wm[2];
                }
            }
        }
    }

  thread_local std::vector<HessianTerm> terms;
  const auto weighted = [&](const double *w, const std::array<Vector3, 8> &w_a, FullMatrix<double> &D) {
    double W[8][8] = {};
    for (unsigned int r = 0; r < rows.size(); ++r)
      {
        if (w[r] == 0) continue;
        row_hessian(r, angle, terms);
        for (const HessianTerm &h : terms) W[h.a][h.b] += w[r] * h.c;
      }
    // sum_ab W_ab J_a^T Y_b, marker side by marker side: Z = sum_b W_ab Y_b (the 4 x 3 rows of
    // side A's vectors, B's columns), then J_A^T Z in one product of inner size 12. Taken pair
    // by pair (a, b), the same sum was some 16 rank-3 updates per side pair, the most costly
    // part of a joint's Jacobian.
    thread_local std::vector<double> JA, Z, block;
    for (unsigned int A = 0; A < 2; ++A)
      {
        const Side &Sa = side[A];
        const int na = Sa.nv + Sa.n_own;
        if (na == 0) continue;
        JA.resize(std::size_t(na) * 12); // na x 12, column-major: (i, 3 x + c) = J_x(c, i)
        for (unsigned int x = 0; x < 4; ++x)
          for (unsigned int c = 0; c < 3; ++c)
            for (int i = 0; i < na; ++i) JA[i + std::size_t(na) * (3 * x + c)] = (*Sa.J[x])(c, i);
        for (unsigned int B = 0; B < 2; ++B)
          {
            const Side &Sb = side[B];
            const int nc = Sb.nq + Sb.n_own;
            bool coupled = false;
            for (unsigned int x = 0; x < 4; ++x)
              for (unsigned int z = 0; z < 4; ++z) coupled = coupled || W[4 * A + x][4 * B + z] != 0;
            if (nc == 0 || !coupled) continue;
            Z.assign(std::size_t(12) * nc, 0.0); // 12 x nc, column-major
            for (unsigned int x = 0; x < 4; ++x)
              for (unsigned int z = 0; z < 4; ++z)
                if (const double w_xz = W[4 * A + x][4 * B + z]; w_xz != 0)
                  for (int k = 0; k < nc; ++k)
                    for (unsigned int c = 0; c < 3; ++c) Z[3 * x + c + 12 * std::size_t(k)] += w_xz * Sb.Y[z](c, k);
            block.resize(std::size_t(na) * nc);
            const int twelve = 12;
            const double one = 1, zero = 0;
            dgemm_("N", "N", &na, &nc, &twelve, &one, JA.data(), &na, Z.data(), &twelve, &zero, block.data(), &na);
            for (int k = 0; k < nc; ++k)
              for (int i = 0; i < na; ++i) D(v_row(Sa, i), q_column(Sb, k)) += block[i + std::size_t(na) * k];
          }
        // H_a(w_a) in closed form; a marker without one had it added with its differences
        for (unsigned int x = 0; x < 4; ++x)
          if (Sa.form && w_a[4 * A + x].norm_square() != 0) Sa.fixed.add_H(x, w_a[4 * A + x], D, Sa.v0, Sa.q0);
      }
  };
  weighted(lambda, w_lambda, d.lambda_q);
  weighted(mu, w_mu, d.mu_q);

  d.rate_q.reinit(rows.size(), nq_total + n_own);
  const auto add_row_times = [&](const unsigned int r, const double c, const Vector3 &x, const unsigned int b,
                                 const FullMatrix<double> &M) { // row r += c x^T M (columns of marker b / 4)
    const Side &S = side[b / 4];
    for (unsigned int k = 0; k < S.nq + S.n_own; ++k)
      d.rate_q(r, q_column(S, k)) += c * (x[0] * M(0, k) + x[1] * M(1, k) + x[2] * M(2, k));
  };
  for (unsigned int r = 0; r < rows.size(); ++r)
    {
      row_hessian(r, angle, terms);
      for (const HessianTerm &h : terms) add_row_times(r, h.c, side[h.a / 4].u[h.a % 4], h.b, side[h.b / 4].Y[h.b % 4]);
      for (unsigned int a = 0; a < 8; ++a)
        if ((side[a / 4].nv > 0 || !side[a / 4].form) && l.grad[r][a].norm_square() != 0)
          add_row_times(r, 1, l.grad[r][a], a, side[a / 4].V[a % 4]);
      if (rows[r].kind == RowKind::angle) // Phi_t = -(e_i,x . (cos th e_j,x + sin th e_j,y)) th'
        {
          const double c = std::cos(angle), sn = std::sin(angle);
          const Vector3 &ei = l.k[0].axes[0];
          add_row_times(r, -angle_rate, c * l.k[1].axes[0] + sn * l.k[1].axes[1], 1, side[0].Y[1]);
          add_row_times(r, -angle_rate * c, ei, 5, side[1].Y[1]);
          add_row_times(r, -angle_rate * sn, ei, 6, side[1].Y[2]);
        }
    }
  return true;
}
} // namespace flextrack::multibody
