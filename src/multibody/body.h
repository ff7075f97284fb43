// Bodies of a multibody system and their coordinates.
//
// A floating body carries a body frame (origin R, rotation A) and, if flexible, modal coordinates
// eta of its reduced body. Position coordinates q_b = (R [3] global, p [4] Euler parameters,
// eta [n]); velocity coordinates v_b = (R' [3] global, omega [3] body axes, eta' [n]).
// The kinematic map q' = T(q) v is the identity except for p' = G(p)^T omega / 2
// (geometry/rotation.h). Why omega and not p': the mass matrix and the quadratic-velocity vector
// of the invariants (reduction/inertia_invariants.h) are written in omega, the Euler-parameter
// mass matrix would be singular along p, and the normalisation |p| = 1 then needs no velocity
// constraint (G p = 0 makes it hold at velocity level by construction).
//
// One class serves rigid and flexible bodies: a rigid body is a floating-frame body with no
// modes (its invariants are m, s = m c, J_O), so the mass matrix and the quadratic-velocity
// vector come from the same FloatingFrameInertia. The ground has no coordinates.
//
// Units: SI throughout (m, kg, s, rad, N).
#pragma once

#include <geometry/rotation.h>
#include <reduction/inertia_invariants.h>
#include <reduction/reduced_body.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <string>

namespace flextrack::multibody
{
using geometry::Matrix3;
using geometry::Vector3;

/// Position and velocity of a body frame, unpacked from the coordinates.
struct FrameState
{
  Vector3 R;                     ///< origin [m], global
  geometry::EulerParameters p;   ///< as stored (not normalised)
  Matrix3 A;                     ///< body to global (of p / |p|)
  dealii::Vector<double> eta;    ///< modal coordinates
  Vector3 R_dot;                 ///< [m/s], global
  Vector3 omega;                 ///< [rad/s], body axes
  dealii::Vector<double> eta_dot;
};

/// Initial state of a floating body.
struct InitialState
{
  Vector3 position;                            ///< body-frame origin R [m], global
  geometry::EulerParameters orientation{{1, 0, 0, 0}};
  Vector3 velocity;                            ///< R' [m/s], global
  Vector3 angular_velocity;                    ///< [rad/s], global axes
  dealii::Vector<double> modal, modal_velocity; ///< eta, eta' (empty: zero)
};

class Body
{
public:
  explicit Body(std::string name) : body_name(std::move(name)) {}
  virtual ~Body() = default;
  const std::string &name() const { return body_name; }

  virtual unsigned int n_q() const = 0;
  virtual unsigned int n_v() const = 0;
  virtual unsigned int n_modes() const { return 0; }
  bool is_ground() const { return n_v() == 0; }
  /// Name of position coordinate @p i or velocity coordinate @p i (for messages).
  virtual std::string q_name(unsigned int i) const = 0;
  virtual std::string v_name(unsigned int i) const = 0;

  /// The coordinates at the start, before they are made consistent.
  virtual void initial_coordinates(double *q, double *v) const = 0;
  /// q' = T(q) v.
  virtual void coordinate_rates(const double *q, const double *v, double *q_dot) const = 0;
  /// M(q), n_v x n_v [kg, kg m, kg m^2].
  virtual void mass_matrix(const double *q, dealii::FullMatrix<double> &M) const = 0;
  /// M(q) v_dot (n_v entries each), for the residual: by default through mass_matrix().
  virtual void mass_times(const double *q, const double *v_dot, double *Mv) const;
  /// Q(q, v): quadratic-velocity, elastic, damping and gravity forces in v-coordinates.
  /// @p v_dot (n_v entries, or nullptr: taken as zero) enters only where a force depends on the
  /// accelerations: the geometric stiffness of a flexible body's inertial loads.
  virtual void forces(const double *q, const double *v, const Vector3 &gravity, double *Q,
                      const double *v_dot = nullptr) const = 0;
  /// Whether forces() depends on the frame accelerations v_dot[0..5].
  virtual bool forces_depend_on_acceleration() const { return false; }
  /// Derivatives of the equations of motion F = M(q) v_dot - Q(q, v, v_dot) (n_v rows), exact:
  /// @p dF_dq (n_v x n_q), @p dF_dv (n_v x n_v) and @p dF_dv_dot (n_v x n_v: M, plus -dQ/dv_dot
  /// where forces depend on the frame accelerations).
  virtual void equation_jacobians(const double *q, const double *v, const double *v_dot, const Vector3 &gravity,
                                  dealii::FullMatrix<double> &dF_dq, dealii::FullMatrix<double> &dF_dv,
                                  dealii::FullMatrix<double> &dF_dv_dot) const = 0;

  virtual double kinetic_energy(const double *q, const double *v) const = 0;       ///< [J]
  virtual double gravity_potential(const double *q, const Vector3 &gravity) const = 0; ///< [J]
  virtual double strain_energy(const double *q) const = 0;                          ///< [J]
  virtual double dissipation_power(const double *q, const double *v) const = 0;      ///< [W], >= 0
  /// Linear momentum [kg m/s] and angular momentum about the global origin [kg m^2/s], global.
  virtual void momentum(const double *q, const double *v, Vector3 &linear, Vector3 &angular) const = 0;

private:
  std::string body_name;
};

/// The fixed frame: no coordinates.
class Ground : public Body
{
public:
  explicit Ground(std::string name = "ground") : Body(std::move(name)) {}
  unsigned int n_q() const override { return 0; }
  unsigned int n_v() const override { return 0; }
  std::string q_name(unsigned int) const override { return ""; }
  std::string v_name(unsigned int) const override { return ""; }
  void initial_coordinates(double *, double *) const override {}
  void coordinate_rates(const double *, const double *, double *) const override {}
  void mass_matrix(const double *, dealii::FullMatrix<double> &M) const override { M.reinit(0, 0); }
  void forces(const double *, const double *, const Vector3 &, double *, const double * = nullptr) const override {}
  void equation_jacobians(const double *, const double *, const double *, const Vector3 &, dealii::FullMatrix<double> &,
                          dealii::FullMatrix<double> &, dealii::FullMatrix<double> &) const override
  {
  }
  double kinetic_energy(const double *, const double *) const override { return 0; }
  double gravity_potential(const double *, const Vector3 &) const override { return 0; }
  double strain_energy(const double *) const override { return 0; }
  double dissipation_power(const double *, const double *) const override { return 0; }
  void momentum(const double *, const double *, Vector3 &l, Vector3 &a) const override { l = a = Vector3(); }
};

/// Mass properties of a rigid body, in body axes.
struct RigidProperties
{
  double mass = 1;                  ///< [kg]
  Vector3 centre_of_mass;           ///< [m], body axes, from the body-frame origin
  Matrix3 inertia_centre_of_mass;   ///< [kg m^2], body axes, about the centre of mass
};

/// Options of a flexible body.
struct FlexibleOptions
{
  bool geometric_stiffening = true; ///< K_eff = K + sum_c a_c(omega, A^T R'' - g, omega') G_c
  bool make_rigid = false;          ///< same invariants m, s, J_O, no modes
};

/// A rigid or reduced flexible body whose frame floats (R, p) in space.
class FloatingBody : public Body
{
public:
  /// A rigid body with the given mass properties.
  FloatingBody(std::string name, const RigidProperties &properties, const InitialState &initial);
  /// A reduced flexible body (or, with options.make_rigid, its rigid twin).
  FloatingBody(std::string name, std::shared_ptr<const reduction::ReducedBody> body, const FlexibleOptions &options,
               const InitialState &initial);

  unsigned int n_q() const override { return 7 + n; }
  unsigned int n_v() const override { return 6 + n; }
  unsigned int n_modes() const override { return n; }
  std::string q_name(unsigned int i) const override;
  std::string v_name(unsigned int i) const override;
  /// The reduced body (null for a rigid body or a flexible body made rigid).
  const reduction::ReducedBody *reduced_body() const { return n > 0 ? reduced.get() : nullptr; }
  /// The reduced body it was made from, also when made rigid (its interfaces); null if rigid.
  const reduction::ReducedBody *source() const { return reduced.get(); }
  const reduction::InertiaInvariants &invariants() const { return inv; }
  bool geometric_stiffening() const { return stiffening; }
  /// Angular frequency of each modal coordinate [rad/s]: sqrt(K_kk / M_kk) of the reduced
  /// matrices (exact for the diagonalised bases of reduction/, a Rayleigh quotient otherwise).
  std::vector<double> modal_angular_frequencies() const;

  FrameState frame(const double *q, const double *v = nullptr) const;
  void initial_coordinates(double *q, double *v) const override;
  void coordinate_rates(const double *q, const double *v, double *q_dot) const override;
  void mass_matrix(const double *q, dealii::FullMatrix<double> &M) const override;
  void mass_times(const double *q, const double *v_dot, double *Mv) const override;
  void forces(const double *q, const double *v, const Vector3 &gravity, double *Q,
              const double *v_dot = nullptr) const override;
  bool forces_depend_on_acceleration() const override { return stiffening; }
  void equation_jacobians(const double *q, const double *v, const double *v_dot, const Vector3 &gravity,
                          dealii::FullMatrix<double> &dF_dq, dealii::FullMatrix<double> &dF_dv,
                          dealii::FullMatrix<double> &dF_dv_dot) const override;
  double kinetic_energy(const double *q, const double *v) const override;
  double gravity_potential(const double *q, const Vector3 &gravity) const override;
  double strain_energy(const double *q) const override;
  double dissipation_power(const double *q, const double *v) const override;
  void momentum(const double *q, const double *v, Vector3 &linear, Vector3 &angular) const override;

  /// Parameters of a rigid body (entries in the current subsection).
  static void declare_rigid_parameters(dealii::ParameterHandler &prm);
  static RigidProperties parse_rigid_parameters(dealii::ParameterHandler &prm);
  /// Initial state entries (position, orientation, velocities, modal coordinates).
  static void declare_initial_state_parameters(dealii::ParameterHandler &prm);
  static InitialState parse_initial_state_parameters(dealii::ParameterHandler &prm, const std::string &entry_prefix);
  /// Options of a flexible body (the reduced body itself is found by the scene reader).
  static void declare_flexible_parameters(dealii::ParameterHandler &prm);
  static FlexibleOptions parse_flexible_parameters(dealii::ParameterHandler &prm);

private:
  unsigned int n = 0;
  std::shared_ptr<const reduction::ReducedBody> reduced;
  reduction::InertiaInvariants inv;
  std::unique_ptr<reduction::FloatingFrameInertia> inertia;
  dealii::FullMatrix<double> K, D; // n x n
  bool stiffening = false;
  InitialState start;
};
} // namespace flextrack::multibody
