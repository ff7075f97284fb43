// Forces between or on markers, as generalised forces in the bodies' velocity coordinates:
// a force F and torque T (global) at a marker contribute J_position^T F + J_rotation^T T.
//   applied load:              F(t), T(t) given as expressions of t, in global or marker axes
//   spring-damper:             f = k (L - L0) + c L' along the line between two markers
//   rotational spring-damper:  T = k (th - th0) + c th' about the z axis of the second marker
//                              (th = atan2(e1_x . e2_y, e1_x . e2_x): use it with a revolute
//                              joint, |th - th0| < pi)
// Each kind also gives its share of the energy balance: potential energy (springs), dissipated
// power (dampers) and power put in (applied loads).
#pragma once

#include <geometry/expression.h>
#include <multibody/joint_table.h>
#include <multibody/marker.h>

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <memory>
#include <vector>

namespace flextrack::multibody
{
class Force
{
public:
  explicit Force(std::string name) : force_name(std::move(name)) {}
  virtual ~Force() = default;
  const std::string &name() const { return force_name; }
  virtual std::vector<const Body *> bodies() const = 0;
  /// Adds the generalised forces to @p Q[b] (v-coordinates of body b of bodies()).
  virtual void add_forces(const std::vector<const double *> &q, const std::vector<const double *> &v, double t,
                          const std::vector<double *> &Q) const = 0;
  /// dQ/dq and dQ/dv of the generalised forces (rows: the v of bodies() in order; columns: their
  /// q, resp. v), analytic. False where the force has none (the system then takes central
  /// differences): the default, a marker not of body-fixed form, or both markers on one body.
  virtual bool derivatives(const std::vector<const double *> & /*q*/, const std::vector<const double *> & /*v*/,
                           double /*t*/, dealii::FullMatrix<double> & /*dQ_dq*/, dealii::FullMatrix<double> & /*dQ_dv*/) const
  {
    return false;
  }
  virtual double potential_energy(const std::vector<const double *> &) const { return 0; }                      ///< [J]
  virtual double dissipation_power(const std::vector<const double *> &, const std::vector<const double *> &) const { return 0; } ///< [W]
  virtual double applied_power(const std::vector<const double *> &, const std::vector<const double *> &, double) const { return 0; } ///< [W]

private:
  std::string force_name;
};

/// Wrench (F, T) at a marker into generalised forces.
void add_wrench(const MarkerKinematics &k, const Vector3 &force, const Vector3 &torque, double *Q);

class AppliedLoad : public Force
{
public:
  /// Components of the force [N] and torque [N m] as expressions of t; in the marker's axes if
  /// @p marker_axes, else global.
  AppliedLoad(std::string name, std::unique_ptr<Marker> marker, std::array<geometry::Expression, 3> force,
              std::array<geometry::Expression, 3> torque, bool marker_axes);
  std::vector<const Body *> bodies() const override { return {&marker->body()}; }
  void add_forces(const std::vector<const double *> &q, const std::vector<const double *> &v, double t,
                  const std::vector<double *> &Q) const override;
  double applied_power(const std::vector<const double *> &q, const std::vector<const double *> &v, double t) const override;
  bool derivatives(const std::vector<const double *> &q, const std::vector<const double *> &v, double t,
                   dealii::FullMatrix<double> &dQ_dq, dealii::FullMatrix<double> &dQ_dv) const override;

private:
  void wrench(const MarkerKinematics &k, double t, Vector3 &F, Vector3 &T) const;
  std::unique_ptr<Marker> marker;
  std::array<geometry::Expression, 3> force, torque;
  bool marker_axes;
};

class SpringDamper : public Force
{
public:
  /// @p stiffness [N/m], @p damping [N s/m], @p free_length [m] (> 0).
  SpringDamper(std::string name, std::unique_ptr<Marker> m1, std::unique_ptr<Marker> m2, double stiffness,
               double damping, double free_length);
  std::vector<const Body *> bodies() const override { return {&m[0]->body(), &m[1]->body()}; }
  void add_forces(const std::vector<const double *> &q, const std::vector<const double *> &v, double t,
                  const std::vector<double *> &Q) const override;
  double potential_energy(const std::vector<const double *> &q) const override;
  double dissipation_power(const std::vector<const double *> &q, const std::vector<const double *> &v) const override;
  bool derivatives(const std::vector<const double *> &q, const std::vector<const double *> &v, double t,
                   dealii::FullMatrix<double> &dQ_dq, dealii::FullMatrix<double> &dQ_dv) const override;

private:
  /// Length, its rate, unit direction (from marker 2 to 1), kinematics.
  void state(const std::vector<const double *> &q, const std::vector<const double *> &v, double &L, double &L_dot,
             Vector3 &n, MarkerKinematics k[2]) const;
  std::unique_ptr<Marker> m[2];
  double k_s, c_d, L0;
};

class RotationalSpringDamper : public Force
{
public:
  /// @p stiffness [N m/rad], @p damping [N m s/rad], @p free_angle [rad].
  RotationalSpringDamper(std::string name, std::unique_ptr<Marker> m1, std::unique_ptr<Marker> m2, double stiffness,
                         double damping, double free_angle);
  std::vector<const Body *> bodies() const override { return {&m[0]->body(), &m[1]->body()}; }
  void add_forces(const std::vector<const double *> &q, const std::vector<const double *> &v, double t,
                  const std::vector<double *> &Q) const override;
  double potential_energy(const std::vector<const double *> &q) const override;
  double dissipation_power(const std::vector<const double *> &q, const std::vector<const double *> &v) const override;
  bool derivatives(const std::vector<const double *> &q, const std::vector<const double *> &v, double t,
                   dealii::FullMatrix<double> &dQ_dq, dealii::FullMatrix<double> &dQ_dv) const override;

private:
  void state(const std::vector<const double *> &q, const std::vector<const double *> &v, double &angle, double &rate,
             MarkerKinematics k[2]) const;
  std::unique_ptr<Marker> m[2];
  double k_s, c_d, th0;
};

/// Entries of a `subsection Force NAME` (Kind and the entries of every kind).
void declare_force_parameters(dealii::ParameterHandler &prm);
/// The force of the current subsection; InputError naming "Force NAME/..." for bad input. Its
/// load laws are checked over the run's @p window (geometry/time_law.h; empty: not checked).
std::unique_ptr<Force> create_force(const std::string &name, dealii::ParameterHandler &prm, const BodyLookup &bodies,
                                    const geometry::TimeWindow &window = {});
} // namespace flextrack::multibody
