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

  /// A marker at the global position @p position with global axes @p axes (columns) at the body's
  /// coordinates @p q (its initial pose): transformed into body axes. On a flexible body
  /// @p interface names the reduced body's interface it sits on (its position is used; empty: a
  /// point that does not move with the modes).
  static std::unique_ptr<FixedMarker> at_global_pose(const Body &body, std::string name, const Vector3 &position,
                                                     const Matrix3 &axes, const double *q,
                                                     const std::string &interface = "");

private:
  dealii::Point<3> x0;
  Matrix3 a0;                      ///< columns: axes in body axes
  dealii::FullMatrix<double> phi;  ///< 6 x n
};
} // namespace flextrack::multibody
