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
