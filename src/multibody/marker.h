// Markers: places on bodies where joints and forces attach.
//
// A marker has a position r and three axes e_1, e_2, e_3 (global), and the Jacobians of these
// with respect to the velocity coordinates of its body (and of the marker's own coordinates, if
// it has any - a track contact at arc length s owns s; a joint that uses such a marker carries
// the coordinate):  r' = J_r v,  e_a' = J_e[a] v,  omega_marker = J_w v (global axes).
//
// The marker kind here is a point and frame fixed on a body. On a flexible body it sits at an
// interface of the reduced body and moves with the interface's 6 x n mode shapes
// (Phi_u translations, Phi_th small rotations):
//   r = R + A (x + Phi_u eta),   axes  A (I + [Phi_th eta]~) a_0
// (the linearised rotation of the floating-frame formulation; the axes are orthonormal to first
// order in eta). On a rigid body Phi is empty; on the ground the marker is fixed in space.
#pragma once

#include <multibody/body.h>

#include <array>

namespace flextrack::multibody
{
struct MarkerKinematics
{
  Vector3 position;                 ///< [m], global
  std::array<Vector3, 3> axes;      ///< unit axes (to first order in eta), global
  /// 3 x (n_v of the body + own coordinates): r' = J_position v, e_a' = J_axes[a] v,
  /// angular velocity (global) = J_rotation v.
  dealii::FullMatrix<double> J_position, J_rotation;
  std::array<dealii::FullMatrix<double>, 3> J_axes;
};

/// A marker whose position and axes are all of the form  y = delta R + A(p) z(eta)  with
/// z = z0 + Z eta, z0 and Z constant (delta = 1 for the position, 0 for an axis): a point and
/// frame fixed on a rigid body or at an interface of a flexible one. Its velocities are then
/// y' = delta R' + A (omega x z + Z eta'), and every second derivative that an analytic joint
/// Jacobian needs follows from z0 and Z (generic_joint.cc).
struct BodyFixedForm
{
  std::array<Vector3, 4> z0;                  ///< position x0 [m], then the axes a0_c, body axes
  std::array<dealii::FullMatrix<double>, 4> Z; ///< 3 x n_modes: Phi_u, then -a0_c~ Phi_th
  dealii::FullMatrix<double> Z_rotation;       ///< 3 x n_modes: Phi_th (omega_global = A (omega + Phi_th eta'))
};

/// Second-order kinematics of a marker of body-fixed form on a body that moves (not the ground),
/// at positions q and velocities v of its body. Quantities a: 0 the position, 1-3 the axes,
/// 4 the angular velocity (J_rotation). Columns: the body's q = (R, p, eta); rows of add_H: its
/// v = (R', omega, eta'). With c = 2 / |p|^2, G = G(p) (omega = c G p' for the A of p / |p|):
///   Y_a = dy_a/dq = J_a T^+                                          (a = 0..3)
///   V_a = d(J_a v)/dq:  -c A s_a~ G (p columns), A omega~ Z_a (eta columns), s_a = omega x z_a + Z_a eta';
///                       for a = 4: -c A s~ G with s = omega + Phi_th eta'
///   H_a(w) = d(J_a^T w)/dq, b = A^T w:  omega rows  c z_a~ b~ G (p), -b~ Z_a (eta); eta rows  c Z_a^T b~ G (p);
///                       for a = 4: omega rows c b~ G, eta rows c Phi_th^T b~ G (p columns).
class BodyFixedDerivatives
{
public:
  void reinit(const BodyFixedForm &form, const Body &body, const double *q, const double *v, const MarkerKinematics &k);
  const dealii::FullMatrix<double> &Y(unsigned int a) const { return y[a]; }
  const dealii::FullMatrix<double> &V(unsigned int a) const { return velocity[a]; }
  /// D(row0 + i, col0 + k) += H_a(w)(i, k).
  void add_H(unsigned int a, const Vector3 &w, dealii::FullMatrix<double> &D, unsigned int row0, unsigned int col0) const;

private:
  const BodyFixedForm *f = nullptr;
  unsigned int n = 0;
  Matrix3 A;
  double c = 0;
  std::array<std::array<double, 4>, 3> G;
  std::array<Vector3, 4> z;
  std::array<dealii::FullMatrix<double>, 4> y;
  std::array<dealii::FullMatrix<double>, 5> velocity;
};

/// Derivatives of a marker's Jacobians with respect to one modal coordinate eta_k of its body,
/// for a marker whose J_position and J_axes are affine in eta and depend on it only in their
/// angular-velocity columns and their own coordinate's column (a track contact): index 0 is
/// J_position, 1..3 J_axes[0..2].
struct ModalJacobianDerivative
{
  std::array<Matrix3, 4> omega; ///< d J / d eta_k in the omega columns (3 x 3)
  std::array<Vector3, 4> own;   ///< d J / d eta_k in the column of the (single) own coordinate
};

class Marker
{
public:
  Marker(const Body &body, std::string name) : on(&body), marker_name(std::move(name)) {}
  virtual ~Marker() = default;
  const Body &body() const { return *on; }
  const std::string &name() const { return marker_name; }
  /// Coordinates that the marker adds (a joint using it carries them); 0 for a fixed marker.
  virtual unsigned int n_own_coordinates() const { return 0; }
  /// Initial values of the own coordinates and their rates.
  virtual void initial_own_coordinates(double * /*q*/, double * /*v*/) const {}
  /// Position, axes and Jacobians for body coordinates @p q, and own coordinates @p own.
  virtual void evaluate(const double *q, const double *own, MarkerKinematics &k) const = 0;
  /// The unit axes alone (global; MarkerKinematics::axes), without the Jacobians: what a driven
  /// angle's rate needs at every step. The default evaluates everything.
  virtual void axes(const double *q, const double *own, std::array<Vector3, 3> &e) const;
  /// Its body-fixed form, if it has one (see BodyFixedForm); nullptr otherwise (a track contact,
  /// whose z depends on its arc length too).
  virtual const BodyFixedForm *body_fixed_form() const { return nullptr; }
  /// For a marker without a body-fixed form: whether its Jacobians are of the form of
  /// ModalJacobianDerivative and independent of the frame origin R, and then their derivatives
  /// for every mode of its body (@p d resized to n_modes()), at body coordinates @p q and own
  /// coordinates @p own. A joint differences the Jacobians of a marker that returns false.
  virtual bool modal_jacobian_derivatives(const double * /*q*/, const double * /*own*/,
                                          std::vector<ModalJacobianDerivative> & /*d*/) const
  {
    return false;
  }

private:
  const Body *on;
  std::string marker_name;
};

/// A point and frame fixed on a body (ground, rigid, or an interface of a flexible body).
class FixedMarker : public Marker
{
public:
  /// @p point [m] and @p frame (columns: axes) in body axes; @p modes: 6 x n interface mode
  /// shapes (empty for a rigid body, the ground, or any point that is not an interface).
  FixedMarker(const Body &body, std::string name, const dealii::Point<3> &point, const Matrix3 &frame,
              const dealii::FullMatrix<double> &modes = dealii::FullMatrix<double>());
  void evaluate(const double *q, const double *own, MarkerKinematics &k) const override;
  void axes(const double *q, const double *own, std::array<Vector3, 3> &e) const override;
  const BodyFixedForm *body_fixed_form() const override { return &form; }

  /// A marker at the global position @p position with global axes @p axes (columns) at the body's
  /// coordinates @p q (its initial pose): transformed into body axes. On a flexible body
  /// @p interface names the reduced body's interface it sits on (its position is used; empty: a
  /// point that does not move with the modes).
  static std::unique_ptr<FixedMarker> at_global_pose(const Body &body, std::string name, const Vector3 &position,
                                                     const Matrix3 &axes, const double *q,
                                                     const std::string &interface = "");

private:
  /// Axis @p c in body axes after the small rotation @p theta of its point: a0_c + theta x a0_c.
  Vector3 deformed_axis(unsigned int c, const Vector3 &theta) const;

  dealii::Point<3> x0;
  Matrix3 a0;                      ///< columns: axes in body axes
  dealii::FullMatrix<double> phi;  ///< 6 x n
  BodyFixedForm form;              ///< the same, as z0 and Z (set once)
};
} // namespace flextrack::multibody
