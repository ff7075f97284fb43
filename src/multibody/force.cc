// Force elements: applied loads, translational and rotational spring-dampers (see force.h).
#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>
#include <multibody/force.h>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
Vector3 times(const FullMatrix<double> &J, const double *v)
{
  Vector3 r;
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int c = 0; c < J.n(); ++c) r[a] += J(a, c) * v[c];
  return r;
}

// Analytic derivatives of the forces (Force::derivatives): each force is J_r^T F + J_w^T T at
// its markers, so  dQ/dq = J_r^T dF/dq + H_r(F) + J_w^T dT/dq + H_w(T)  and  dQ/dv = J_r^T dF/dv +
// J_w^T dT/dv, with H = d(J^T w)/dq at fixed w and the markers' Y = dy/dq, V = d(J v)/dq from
// BodyFixedDerivatives (marker.h). Marker quantities: 0 position, 1-3 axes, 4 angular velocity.

/// One marker of a force: its kinematics, second-order terms and place in the force's columns.
struct End
{
  unsigned int nq = 0, nv = 0, q0 = 0, v0 = 0;
  MarkerKinematics k;
  BodyFixedDerivatives d;
};

const FullMatrix<double> &jacobian(const MarkerKinematics &k, const unsigned int a)
{
  return a == 0 ? k.J_position : a == 4 ? k.J_rotation : k.J_axes[a - 1];
}

/// Evaluates @p markers at (q, v) into @p ends and sizes dQ/dq and dQ/dv; false if a marker has
/// no body-fixed form or two share a body (their columns would repeat).
bool prepare(const std::vector<const Marker *> &markers, const std::vector<const double *> &q,
             const std::vector<const double *> &v, std::vector<End> &ends, FullMatrix<double> &dQ_dq,
             FullMatrix<double> &dQ_dv)
{
  ends.resize(markers.size());
  unsigned int nq = 0, nv = 0;
  for (unsigned int i = 0; i < markers.size(); ++i)
    {
      const BodyFixedForm *form = markers[i]->body_fixed_form();
      if (!form) return false;
      for (unsigned int j = 0; j < i; ++j)
        if (&markers[j]->body() == &markers[i]->body()) return false;
      End &e = ends[i];
      const Body &body = markers[i]->body();
      e.nq = body.n_q(), e.nv = body.n_v(), e.q0 = nq, e.v0 = nv;
      nq += e.nq, nv += e.nv;
      markers[i]->evaluate(q[i], nullptr, e.k);
      if (e.nv) e.d.reinit(*form, body, q[i], v[i], e.k);
    }
  dQ_dq.reinit(nv, nq);
  dQ_dv.reinit(nv, nv);
  return true;
}

/// D(rows of @p at, columns col0 + k) += J_a(at)^T M  (M: 3 x columns).
void add_jacobian_transpose_times(const End &at, const unsigned int a, const FullMatrix<double> &M, const unsigned int col0,
                                  FullMatrix<double> &D)
{
  const FullMatrix<double> &J = jacobian(at.k, a);
  for (unsigned int i = 0; i < at.nv; ++i)
    for (unsigned int k = 0; k < M.n(); ++k) D(at.v0 + i, col0 + k) += J(0, i) * M(0, k) + J(1, i) * M(1, k) + J(2, i) * M(2, k);
}

/// Equal and opposite at the two ends: D += J_a(end 1)^T M - J_a(end 2)^T M.
void add_to_both_ends(const std::vector<End> &ends, const unsigned int a, const FullMatrix<double> &M, const unsigned int col0,
                      FullMatrix<double> &D)
{
  add_jacobian_transpose_times(ends[0], a, M, col0, D);
  FullMatrix<double> minus(M);
  minus *= -1;
  add_jacobian_transpose_times(ends[1], a, minus, col0, D);
}

/// x^T M: a row (M: 3 x columns).
std::vector<double> row_times(const Vector3 &x, const FullMatrix<double> &M)
{
  std::vector<double> r(M.n());
  for (unsigned int k = 0; k < M.n(); ++k) r[k] = x[0] * M(0, k) + x[1] * M(1, k) + x[2] * M(2, k);
  return r;
}

/// x r^T: 3 x columns.
FullMatrix<double> outer(const Vector3 &x, const std::vector<double> &r)
{
  FullMatrix<double> M(3, r.size());
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int k = 0; k < r.size(); ++k) M(i, k) = x[i] * r[k];
  return M;
}
} // namespace

void add_wrench(const MarkerKinematics &k, const Vector3 &force, const Vector3 &torque, double *Q)
{
  for (unsigned int c = 0; c < k.J_position.n(); ++c)
    for (unsigned int a = 0; a < 3; ++a) Q[c] += k.J_position(a, c) * force[a] + k.J_rotation(a, c) * torque[a];
}

// ---------------------------------------------------------------------------------------------
AppliedLoad::AppliedLoad(std::string name, std::unique_ptr<Marker> m, std::array<geometry::Expression, 3> f,
                         std::array<geometry::Expression, 3> t, const bool axes)
  : Force(std::move(name)), marker(std::move(m)), force(std::move(f)), torque(std::move(t)), marker_axes(axes)
{}

void AppliedLoad::wrench(const MarkerKinematics &k, const double t, Vector3 &F, Vector3 &T) const
{
  F = T = Vector3();
  for (unsigned int a = 0; a < 3; ++a)
    {
      const double f = force[a].value(t), m = torque[a].value(t);
      if (marker_axes)
        {
          F += f * k.axes[a];
          T += m * k.axes[a];
        }
      else
        {
          F[a] = f;
          T[a] = m;
        }
    }
}

void AppliedLoad::add_forces(const std::vector<const double *> &q, const std::vector<const double *> &, const double t,
                             const std::vector<double *> &Q) const
{
  MarkerKinematics k;
  marker->evaluate(q[0], nullptr, k);
  Vector3 F, T;
  wrench(k, t, F, T);
  add_wrench(k, F, T, Q[0]);
}

double AppliedLoad::applied_power(const std::vector<const double *> &q, const std::vector<const double *> &v,
                                  const double t) const
{
  MarkerKinematics k;
  marker->evaluate(q[0], nullptr, k);
  Vector3 F, T;
  wrench(k, t, F, T);
  return F * times(k.J_position, v[0]) + T * times(k.J_rotation, v[0]);
}

bool AppliedLoad::derivatives(const std::vector<const double *> &q, const std::vector<const double *> &v, const double t,
                              FullMatrix<double> &dQ_dq, FullMatrix<double> &dQ_dv) const
{
  std::vector<End> ends;
  if (!prepare({marker.get()}, q, v, ends, dQ_dq, dQ_dv)) return false;
  const End &e = ends[0];
  if (e.nv == 0) return true; // on the ground: no generalised force
  Vector3 F, T;
  wrench(e.k, t, F, T);
  e.d.add_H(0, F, dQ_dq, 0, 0);
  e.d.add_H(4, T, dQ_dq, 0, 0);
  if (marker_axes) // F = sum f_a e_a: dF/dq = sum f_a Y_axis a
    for (unsigned int a = 0; a < 3; ++a)
      {
        FullMatrix<double> dF(e.d.Y(1 + a)), dT(e.d.Y(1 + a));
        dF *= force[a].value(t);
        dT *= torque[a].value(t);
        add_jacobian_transpose_times(e, 0, dF, 0, dQ_dq);
        add_jacobian_transpose_times(e, 4, dT, 0, dQ_dq);
      }
  return true;
}

// ---------------------------------------------------------------------------------------------
SpringDamper::SpringDamper(std::string name, std::unique_ptr<Marker> m1, std::unique_ptr<Marker> m2, const double stiffness,
                           const double damping, const double free_length)
  : Force(std::move(name)), k_s(stiffness), c_d(damping), L0(free_length)
{
  m[0] = std::move(m1);
  m[1] = std::move(m2);
}

void SpringDamper::state(const std::vector<const double *> &q, const std::vector<const double *> &v, double &L,
                         double &L_dot, Vector3 &n, MarkerKinematics k[2]) const
{
  for (unsigned int i = 0; i < 2; ++i) m[i]->evaluate(q[i], nullptr, k[i]);
  const Vector3 d = k[0].position - k[1].position;
  L = d.norm();
  if (L < 1e-12) throw std::runtime_error("spring-damper '" + name() + "': its two points coincide (length 0)");
  n = d / L;
  L_dot = 0;
  if (!v.empty()) L_dot = n * (times(k[0].J_position, v[0]) - times(k[1].J_position, v[1]));
}

void SpringDamper::add_forces(const std::vector<const double *> &q, const std::vector<const double *> &v, double,
                              const std::vector<double *> &Q) const
{
  double L, L_dot;
  Vector3 n;
  MarkerKinematics k[2];
  state(q, v, L, L_dot, n, k);
  const double f = k_s * (L - L0) + c_d * L_dot; // tension [N]
  add_wrench(k[0], -f * n, Vector3(), Q[0]);
  add_wrench(k[1], f * n, Vector3(), Q[1]);
}

bool SpringDamper::derivatives(const std::vector<const double *> &q, const std::vector<const double *> &v, double,
                               FullMatrix<double> &dQ_dq, FullMatrix<double> &dQ_dv) const
{
  // d = r_1 - r_2, L = |d|, n = d / L, L' = n . (u_1 - u_2), f = k (L - L0) + c L'; F_1 = -f n = -F_2.
  std::vector<End> ends;
  if (!prepare({m[0].get(), m[1].get()}, q, v, ends, dQ_dq, dQ_dv)) return false;
  const Vector3 d = ends[0].k.position - ends[1].k.position;
  const double L = d.norm();
  if (L < 1e-12) throw std::runtime_error("spring-damper '" + name() + "': its two points coincide (length 0)");
  const Vector3 n = d / L;
  Vector3 u;
  for (unsigned int i = 0; i < 2; ++i)
    if (ends[i].nv) u += (i == 0 ? 1.0 : -1.0) * times(ends[i].k.J_position, v[i]);
  const double f = k_s * (L - L0) + c_d * (n * u);
  const Vector3 F[2] = {-f * n, f * n};
  for (unsigned int i = 0; i < 2; ++i) // H_r(F) of each end
    if (ends[i].nv) ends[i].d.add_H(0, F[i], dQ_dq, ends[i].v0, ends[i].q0);
  for (unsigned int j = 0; j < 2; ++j) // the columns of end j
    {
      const End &e = ends[j];
      if (e.nv == 0) continue;
      const double sign = j == 0 ? 1.0 : -1.0;
      FullMatrix<double> dd(e.d.Y(0)), du(e.d.V(0)); // dd/dq_j, du/dq_j
      dd *= sign;
      du *= sign;
      // dn/dq_j = (I - n n^T) dd / L
      FullMatrix<double> dn(dd);
      const std::vector<double> n_dd = row_times(n, dd);
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int k = 0; k < dd.n(); ++k) dn(i, k) = (dd(i, k) - n[i] * n_dd[k]) / L;
      const std::vector<double> u_dn = row_times(u, dn), n_du = row_times(n, du);
      std::vector<double> df(dd.n());
      for (unsigned int k = 0; k < dd.n(); ++k) df[k] = k_s * n_dd[k] + c_d * (u_dn[k] + n_du[k]);
      FullMatrix<double> dF = outer(n, df); // dF_1/dq_j = -(n df + f dn)
      dF.add(f, dn);
      dF *= -1;
      add_to_both_ends(ends, 0, dF, e.q0, dQ_dq);
      // dF_1/dv_j = -c n dL'/dv_j, dL'/dv_j = sign n^T J_r,j
      std::vector<double> dL_dot = row_times(n, e.k.J_position);
      for (double &x : dL_dot) x *= sign;
      FullMatrix<double> dFv = outer(n, dL_dot);
      dFv *= -c_d;
      add_to_both_ends(ends, 0, dFv, e.v0, dQ_dv);
    }
  return true;
}

double SpringDamper::potential_energy(const std::vector<const double *> &q) const
{
  double L, L_dot;
  Vector3 n;
  MarkerKinematics k[2];
  state(q, {}, L, L_dot, n, k);
  return 0.5 * k_s * (L - L0) * (L - L0);
}

double SpringDamper::dissipation_power(const std::vector<const double *> &q, const std::vector<const double *> &v) const
{
  double L, L_dot;
  Vector3 n;
  MarkerKinematics k[2];
  state(q, v, L, L_dot, n, k);
  return c_d * L_dot * L_dot;
}

// ---------------------------------------------------------------------------------------------
RotationalSpringDamper::RotationalSpringDamper(std::string name, std::unique_ptr<Marker> m1, std::unique_ptr<Marker> m2,
                                               const double stiffness, const double damping, const double free_angle)
  : Force(std::move(name)), k_s(stiffness), c_d(damping), th0(free_angle)
{
  m[0] = std::move(m1);
  m[1] = std::move(m2);
}

void RotationalSpringDamper::state(const std::vector<const double *> &q, const std::vector<const double *> &v,
                                   double &angle, double &rate, MarkerKinematics k[2]) const
{
  for (unsigned int i = 0; i < 2; ++i) m[i]->evaluate(q[i], nullptr, k[i]);
  angle = std::atan2(k[0].axes[0] * k[1].axes[1], k[0].axes[0] * k[1].axes[0]);
  rate = 0;
  if (!v.empty()) rate = (times(k[0].J_rotation, v[0]) - times(k[1].J_rotation, v[1])) * k[1].axes[2];
}

void RotationalSpringDamper::add_forces(const std::vector<const double *> &q, const std::vector<const double *> &v,
                                        double, const std::vector<double *> &Q) const
{
  double angle, rate;
  MarkerKinematics k[2];
  state(q, v, angle, rate, k);
  const Vector3 T = -(k_s * (angle - th0) + c_d * rate) * k[1].axes[2];
  add_wrench(k[0], Vector3(), T, Q[0]);
  add_wrench(k[1], Vector3(), -T, Q[1]);
}

bool RotationalSpringDamper::derivatives(const std::vector<const double *> &q, const std::vector<const double *> &v,
                                         double, FullMatrix<double> &dQ_dq, FullMatrix<double> &dQ_dv) const
{
  // th = atan2(y, x), x = e1_x . e2_x, y = e1_x . e2_y; rate = (w_1 - w_2) . e2_z;
  // tau = -(k (th - th0) + c rate); T_1 = tau e2_z = -T_2 (torques on the ends).
  std::vector<End> ends;
  if (!prepare({m[0].get(), m[1].get()}, q, v, ends, dQ_dq, dQ_dv)) return false;
  const MarkerKinematics &k1 = ends[0].k, &k2 = ends[1].k;
  const double x = k1.axes[0] * k2.axes[0], y = k1.axes[0] * k2.axes[1], r2 = x * x + y * y;
  const double angle = std::atan2(y, x);
  Vector3 w;
  for (unsigned int i = 0; i < 2; ++i)
    if (ends[i].nv) w += (i == 0 ? 1.0 : -1.0) * times(ends[i].k.J_rotation, v[i]);
  const Vector3 &ez = k2.axes[2];
  const double tau = -(k_s * (angle - th0) + c_d * (w * ez));
  const Vector3 T[2] = {tau * ez, -tau * ez};
  for (unsigned int i = 0; i < 2; ++i) // H_w(T) of each end
    if (ends[i].nv) ends[i].d.add_H(4, T[i], dQ_dq, ends[i].v0, ends[i].q0);
  for (unsigned int j = 0; j < 2; ++j)
    {
      const End &e = ends[j];
      if (e.nv == 0) continue;
      std::vector<double> d_angle, d_rate;
      FullMatrix<double> dT; // dT_1/dq_j = e2_z dtau/dq_j (+ tau de2_z/dq_j)
      if (j == 0)
        {
          d_angle = row_times((x * k2.axes[1] - y * k2.axes[0]) / r2, e.d.Y(1));
          d_rate = row_times(ez, e.d.V(4));
          dT.reinit(3, e.nq);
        }
      else
        {
          const std::vector<double> dy = row_times(k1.axes[0], e.d.Y(2)), dx = row_times(k1.axes[0], e.d.Y(1));
          d_angle.resize(e.nq);
          for (unsigned int k = 0; k < e.nq; ++k) d_angle[k] = (x * dy[k] - y * dx[k]) / r2;
          const std::vector<double> a = row_times(ez, e.d.V(4)), b = row_times(w, e.d.Y(3));
          d_rate.resize(e.nq);
          for (unsigned int k = 0; k < e.nq; ++k) d_rate[k] = -a[k] + b[k];
          dT = e.d.Y(3);
          dT *= tau;
        }
      std::vector<double> d_tau(e.nq);
      for (unsigned int k = 0; k < e.nq; ++k) d_tau[k] = -(k_s * d_angle[k] + c_d * d_rate[k]);
      dT.add(1.0, outer(ez, d_tau));
      add_to_both_ends(ends, 4, dT, e.q0, dQ_dq);
      // dT_1/dv_j = -c e2_z drate/dv_j, drate/dv_j = +-e2_z^T J_w,j
      std::vector<double> dr = row_times(ez, e.k.J_rotation);
      if (j == 1)
        for (double &z : dr) z = -z;
      FullMatrix<double> dTv = outer(ez, dr);
      dTv *= -c_d;
      add_to_both_ends(ends, 4, dTv, e.v0, dQ_dv);
    }
  return true;
}

double RotationalSpringDamper::potential_energy(const std::vector<const double *> &q) const
{
  double angle, rate;
  MarkerKinematics k[2];
  state(q, {}, angle, rate, k);
  return 0.5 * k_s * (angle - th0) * (angle - th0);
}

double RotationalSpringDamper::dissipation_power(const std::vector<const double *> &q, const std::vector<const double *> &v) const
{
  double angle, rate;
  MarkerKinematics k[2];
  state(q, v, angle, rate, k);
  return c_d * rate * rate;
}
} // namespace flextrack::multibody
