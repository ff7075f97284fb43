// Floating-frame bodies: coordinates, mass matrix, generalised forces and energies.
// The inertia terms are those of reduction::FloatingFrameInertia; this file adds the kinematic
// map, gravity, elasticity (with optional geometric stiffening) and modal damping.
#include <base/input_error.h>
#include <base/text.h>
#include <multibody/body.h>

namespace flextrack::multibody
{
using namespace dealii;
using geometry::skew;

namespace
{
reduction::InertiaInvariants rigid_invariants(const RigidProperties &r)
{
  reduction::InertiaInvariants inv;
  inv.mass = r.mass;
  inv.first_moment = r.mass * r.centre_of_mass;
  const Vector3 &c = r.centre_of_mass;
  // Parallel-axis theorem: J_O = J_c + m (|c|^2 1 - c c^T).
  inv.inertia_origin = r.inertia_centre_of_mass + r.mass * ((c * c) * unit_symmetric_tensor<3>() - outer_product(c, c));
  inv.I3.reinit(3, 0);
  inv.I4.reinit(3, 0);
  return inv;
}

/// The invariants of @p body without its modes: the rigid twin has the same m, s, J_O.
reduction::InertiaInvariants without_modes(const reduction::InertiaInvariants &full)
{
  reduction::InertiaInvariants inv;
  inv.mass = full.mass;
  inv.first_moment = full.first_moment;
  inv.inertia_origin = full.inertia_origin;
  inv.I3.reinit(3, 0);
  inv.I4.reinit(3, 0);
  return inv;
}

/// x^T K x for the n x n matrix @p K (n = K.m(); x: n entries), without a copy of x.
double quadratic_form(const FullMatrix<double> &K, const double *x)
{
  double sum = 0;
  for (unsigned int j = 0; j < K.m(); ++j)
    {
      double row = 0;
      for (unsigned int k = 0; k < K.n(); ++k) row += K(j, k) * x[k];
      sum += x[j] * row;
    }
  return sum;
}
} // namespace

void Body::mass_times(const double *q, const double *v_dot, double *Mv) const
{
  FullMatrix<double> M;
  mass_matrix(q, M);
  for (unsigned int i = 0; i < M.m(); ++i)
    {
      Mv[i] = 0;
      for (unsigned int k = 0; k < M.n(); ++k) Mv[i] += M(i, k) * v_dot[k];
    }
}

FloatingBody::FloatingBody(std::string name, const RigidProperties &properties, const InitialState &initial)
  : Body(std::move(name)), n(0), inv(rigid_invariants(properties)), start(initial)
{
  if (!(properties.mass > 0))
    throw InputError("Body " + this->name() + "/Mass", "must be > 0 kg");
  inertia = std::make_unique<reduction::FloatingFrameInertia>(inv, FullMatrix<double>());
}

FloatingBody::FloatingBody(std::string name, std::shared_ptr<const reduction::ReducedBody> body,
                           const FlexibleOptions &options, const InitialState &initial)
  : Body(std::move(name)), reduced(std::move(body)), start(initial)
{
  Assert(reduced, ExcMessage("a flexible body needs its reduced body"));
  if (options.make_rigid)
    {
      n = 0;
      inv = without_modes(reduced->invariants);
      inertia = std::make_unique<reduction::FloatingFrameInertia>(inv, FullMatrix<double>());
    }
  else
    {
      n = reduced->n_modes();
      inv = reduced->invariants;
      inertia = std::make_unique<reduction::FloatingFrameInertia>(inv, reduced->mass);
      K = reduced->stiffness;
      D = reduced->damping.m() == n ? reduced->damping : FullMatrix<double>(n, n);
      stiffening = options.geometric_stiffening && !reduced->geometric_stiffness.empty();
    }
  if (start.modal.size() != 0 && start.modal.size() != n)
    throw InputError("Body " + this->name() + "/Modal coordinates",
                     "gives " + std::to_string(start.modal.size()) + " values, the body has " + std::to_string(n) + " modes");
  if (start.modal_velocity.size() != 0 && start.modal_velocity.size() != n)
    throw InputError("Body " + this->name() + "/Modal velocities",
                     "gives " + std::to_string(start.modal_velocity.size()) + " values, the body has " + std::to_string(n) +
                       " modes");
}

std::string FloatingBody::q_name(const unsigned int i) const
{
  static const char *names[] = {"R_x", "R_y", "R_z", "p0", "p1", "p2", "p3"};
  return i < 7 ? names[i] : "eta_" + std::to_string(i - 7);
}

std::string FloatingBody::v_name(const unsigned int i) const
{
  static const char *names[] = {"R'_x", "R'_y", "R'_z", "omega_x", "omega_y", "omega_z"};
  return i < 6 ? names[i] : "eta'_" + std::to_string(i - 6);
}

FrameState FloatingBody::frame(const double *q, const double *v) const
{
  FrameState f;
  f.R = Vector3({q[0], q[1], q[2]});
  f.p = {{q[3], q[4], q[5], q[6]}};
  f.A = geometry::rotation_matrix(f.p);
  f.eta.reinit(n);
  for (unsigned int k = 0; k < n; ++k) f.eta[k] = q[7 + k];
  f.eta_dot.reinit(n);
  if (v)
    {
      f.R_dot = Vector3({v[0], v[1], v[2]});
      f.omega = Vector3({v[3], v[4], v[5]});
      for (unsigned int k = 0; k < n; ++k) f.eta_dot[k] = v[6 + k];
    }
  return f;
}

void FloatingBody::initial_coordinates(double *q, double *v) const
{
  const Matrix3 A = geometry::rotation_matrix(start.orientation);
  const Vector3 omega = transpose(A) * start.angular_velocity; // body axes
  for (unsigned int a = 0; a < 3; ++a)
    {
      q[a] = start.position[a];
      v[a] = start.velocity[a];
      v[3 + a] = omega[a];
    }
  for (unsigned int a = 0; a < 4; ++a) q[3 + a] = start.orientation[a];
  for (unsigned int k = 0; k < n; ++k)
    {
      q[7 + k] = start.modal.size() ? start.modal[k] : 0.0;
      v[6 + k] = start.modal_velocity.size() ? start.modal_velocity[k] : 0.0;
    }
}

void FloatingBody::coordinate_rates(const double *q, const double *v, double *q_dot) const
{
  const auto G = geometry::body_velocity_matrix({{q[3], q[4], q[5], q[6]}});
  for (unsigned int a = 0; a < 3; ++a) q_dot[a] = v[a];
  for (unsigned int i = 0; i < 4; ++i)
    q_dot[3 + i] = 0.5 * (G[0][i] * v[3] + G[1][i] * v[4] + G[2][i] * v[5]); // p' = G^T omega / 2
  for (unsigned int k = 0; k < n; ++k) q_dot[7 + k] = v[6 + k];
}

void FloatingBody::mass_matrix(const double *q, FullMatrix<double> &M) const
{
  inertia->mass_matrix(geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}}), q + 7, M);
}

void FloatingBody::mass_times(const double *q, const double *v_dot, double *Mv) const
{
  inertia->mass_times(geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}}), q + 7, v_dot, Mv);
}

void FloatingBody::forces(const double *q, const double *v, const Vector3 &gravity, double *Q, const double *v_dot) const
{
  // Straight from q and v (A, omega; eta = q[7..], eta' = v[6..]): no copies per evaluation.
  const Matrix3 A = geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}});
  const Vector3 omega({v[3], v[4], v[5]});
  const double *eta = q + 7, *eta_dot = v + 6;
  thread_local Vector<double> Qv; // reused between calls: no heap allocation per evaluation
  inertia->quadratic_velocity(A, eta, omega, eta_dot, Qv);
  for (unsigned int i = 0; i < 6 + n; ++i) Q[i] = Qv[i];

  // Gravity: V = -g . (m R + A S), S = s + I3 eta.
  const Vector3 g_body = transpose(A) * gravity;
  Vector3 S = inv.first_moment;
  for (unsigned int k = 0; k < n; ++k)
    for (unsigned int a = 0; a < 3; ++a) S[a] += inv.I3(a, k) * eta[k];
  const Vector3 torque = cross_product_3d(S, g_body);
  for (unsigned int a = 0; a < 3; ++a)
    {
      Q[a] += inv.mass * gravity[a];
      Q[3 + a] += torque[a];
    }
  if (n == 0) return;
  for (unsigned int k = 0; k < n; ++k)
    for (unsigned int a = 0; a < 3; ++a) Q[6 + k] += inv.I3(a, k) * g_body[a];

  // Elastic and damping forces. Geometric stiffening takes the inertial load of the frame's
  // motion - its rotation omega, the acceleration of its origin A^T R'' less gravity, and its
  // angular acceleration omega' (body axes; the last two from v_dot) - which the body's supports
  // or the joint at its frame interface carry. A beam clamped to a hub off the spin axis gets the
  // tension of its root's centripetal acceleration this way.
  Vector3 acceleration = -g_body, angular_acceleration;
  if (v_dot)
    {
      acceleration += transpose(A) * Vector3({v_dot[0], v_dot[1], v_dot[2]});
      angular_acceleration = Vector3({v_dot[3], v_dot[4], v_dot[5]});
    }
  thread_local FullMatrix<double> stiffened; // K plus the geometric stiffness (storage reused)
  if (stiffening) stiffened = reduction::stiffness_with_inertial_loads(*reduced, omega, acceleration, angular_acceleration);
  const FullMatrix<double> &K_eff = stiffening ? stiffened : K;
  for (unsigned int j = 0; j < n; ++j)
    for (unsigned int k = 0; k < n; ++k) Q[6 + j] -= K_eff(j, k) * eta[k] + D(j, k) * eta_dot[k];
}

double FloatingBody::kinetic_energy(const double *q, const double *v) const
{
  thread_local std::vector<double> Mv;
  Mv.resize(n_v());
  mass_times(q, v, Mv.data());
  double twice = 0;
  for (unsigned int i = 0; i < n_v(); ++i) twice += v[i] * Mv[i];
  return 0.5 * twice;
}

double FloatingBody::gravity_potential(const double *q, const Vector3 &gravity) const
{
  const FrameState f = frame(q);
  Vector3 S = inv.first_moment;
  for (unsigned int k = 0; k < n; ++k)
    for (unsigned int a = 0; a < 3; ++a) S[a] += inv.I3(a, k) * f.eta[k];
  return -(gravity * (inv.mass * f.R + f.A * S));
}

std::vector<double> FloatingBody::modal_angular_frequencies() const
{
  std::vector<double> omega(n, 0.0);
  for (unsigned int k = 0; k < n; ++k)
    {
      const double m = reduced->mass(k, k), stiffness = K(k, k);
      omega[k] = m > 0 && stiffness > 0 ? std::sqrt(stiffness / m) : 0.0;
    }
  return omega;
}

double FloatingBody::strain_energy(const double *q) const
{
  return 0.5 * quadratic_form(K, q + 7);
}

double FloatingBody::dissipation_power(const double *, const double *v) const
{
  return quadratic_form(D, v + 6);
}

void FloatingBody::momentum(const double *q, const double *v, Vector3 &linear, Vector3 &angular) const
{
  FullMatrix<double> M;
  mass_matrix(q, M);
  Vector<double> vv(v, v + n_v()), Mv(n_v());
  M.vmult(Mv, vv);
  const FrameState f = frame(q);
  const Vector3 h({Mv[3], Mv[4], Mv[5]}); // body axes: S~ A^T R' + J omega + M_wf eta'
  linear = Vector3({Mv[0], Mv[1], Mv[2]});
  angular = cross_product_3d(f.R, linear) + f.A * h;
}

// ---------------------------------------------------------------------------------------------
// Parameters

void FloatingBody::declare_rigid_parameters(ParameterHandler &prm)
{
  prm.declare_entry("Mass", "1", Patterns::Double(0), "Mass of the body [kg].");
  prm.declare_entry("Centre of mass", "0, 0, 0", Patterns::Anything(),
                    "Centre of mass in body axes, from the body-frame origin [m].");
  prm.declare_entry("Inertia", "1, 1, 1, 0, 0, 0", Patterns::Anything(),
                    "Inertia tensor about the centre of mass in body axes: Jxx, Jyy, Jzz, Jxy, Jyz, Jxz "
                    "[kg m^2] (Jxy = -int rho x y, the tensor's off-diagonal entry).");
}

RigidProperties FloatingBody::parse_rigid_parameters(ParameterHandler &prm)
{
  RigidProperties r;
  r.mass = prm.get_double("Mass");
  const auto c = base::parse_vector3(prm.get("Centre of mass"), "Centre of mass", "m");
  r.centre_of_mass = Vector3({c[0], c[1], c[2]});
  const auto w = base::words(prm.get("Inertia"));
  if (w.size() != 6) throw InputError("Inertia", "needs six numbers Jxx, Jyy, Jzz, Jxy, Jyz, Jxz [kg m^2]");
  double J[6];
  for (unsigned int i = 0; i < 6; ++i) J[i] = base::parse_number(w[i], "Inertia", "an inertia [kg m^2]");
  r.inertia_centre_of_mass[0][0] = J[0];
  r.inertia_centre_of_mass[1][1] = J[1];
  r.inertia_centre_of_mass[2][2] = J[2];
  r.inertia_centre_of_mass[0][1] = r.inertia_centre_of_mass[1][0] = J[3];
  r.inertia_centre_of_mass[1][2] = r.inertia_centre_of_mass[2][1] = J[4];
  r.inertia_centre_of_mass[0][2] = r.inertia_centre_of_mass[2][0] = J[5];
  return r;
}

void FloatingBody::declare_initial_state_parameters(ParameterHandler &prm)
{
  prm.declare_entry("Position", "0, 0, 0", Patterns::Anything(), "Initial body-frame origin, global [m].");
  prm.declare_entry("Rotation vector", "0, 0, 0", Patterns::Anything(),
                    "Initial orientation as a rotation vector (axis times angle), global [rad].");
  prm.declare_entry("Euler parameters", "", Patterns::Anything(),
                    "Initial orientation as Euler parameters p0, p1, p2, p3 [-] (normalised); overrides "
                    "the rotation vector when given.");
  prm.declare_entry("Velocity", "0, 0, 0", Patterns::Anything(), "Initial velocity of the body-frame origin, global [m/s].");
  prm.declare_entry("Angular velocity", "0, 0, 0", Patterns::Anything(), "Initial angular velocity, global axes [rad/s].");
  prm.declare_entry("Modal coordinates", "", Patterns::Anything(),
                    "Initial modal coordinates eta of a flexible body (empty: zero) [modal units].");
  prm.declare_entry("Modal velocities", "", Patterns::Anything(),
                    "Initial modal velocities eta' of a flexible body (empty: zero) [modal units/s].");
}

namespace
{
Vector3 vector_entry(ParameterHandler &prm, const std::string &entry, const std::string &prefix, const std::string &unit)
{
  const auto v = base::parse_vector3(prm.get(entry), prefix + entry, unit);
  return Vector3({v[0], v[1], v[2]});
}

Vector<double> list_entry(ParameterHandler &prm, const std::string &entry, const std::string &prefix)
{
  const auto w = base::words(prm.get(entry));
  Vector<double> v(w.size());
  for (unsigned int i = 0; i < w.size(); ++i) v[i] = base::parse_number(w[i], prefix + entry, "a number");
  return v;
}
} // namespace

InitialState FloatingBody::parse_initial_state_parameters(ParameterHandler &prm, const std::string &prefix)
{
  InitialState s;
  s.position = vector_entry(prm, "Position", prefix, "m");
  s.orientation = geometry::euler_parameters_from_rotation_vector(vector_entry(prm, "Rotation vector", prefix, "rad"));
  const Vector<double> p = list_entry(prm, "Euler parameters", prefix);
  if (p.size() != 0)
    {
      if (p.size() != 4 || p.l2_norm() == 0)
        throw InputError(prefix + "Euler parameters", "needs four numbers p0, p1, p2, p3, not all zero");
      for (unsigned int i = 0; i < 4; ++i) s.orientation[i] = p[i] / p.l2_norm();
    }
  s.velocity = vector_entry(prm, "Velocity", prefix, "m/s");
  s.angular_velocity = vector_entry(prm, "Angular velocity", prefix, "rad/s");
  s.modal = list_entry(prm, "Modal coordinates", prefix);
  s.modal_velocity = list_entry(prm, "Modal velocities", prefix);
  return s;
}

void FloatingBody::declare_flexible_parameters(ParameterHandler &prm)
{
  prm.declare_entry("Geometric stiffening", "true", Patterns::Bool(),
                    "Add the geometric stiffness of the inertial loads (rotation of the body frame, gravity) "
                    "to the modal stiffness [-].");
  prm.declare_entry("Rigid", "false", Patterns::Bool(),
                    "Treat the body as rigid with the same mass properties (m, s, J_O; no modes) [-].");
}

FlexibleOptions FloatingBody::parse_flexible_parameters(ParameterHandler &prm)
{
  FlexibleOptions o;
  o.geometric_stiffening = prm.get_bool("Geometric stiffening");
  o.make_rigid = prm.get_bool("Rigid");
  return o;
}
} // namespace flextrack::multibody
