// A track contact: a marker that slides along an arm of a body, at arc length s (its own
// coordinate), following the deformed arm (seed eqs. 39-40, FORMULATION.md section 2):
//   r(s) = R + A (y(s) + Phi_u(s) eta)
//   axes   A (I + [Phi_th(s) eta]~) (d2, d3, t)(s)
// with the exact centre line y(s) and section frame (t tangent, d2 section y axis, d3 = t x d2)
// from geometry (never an interpolant of them) and the C1 mode fields of the reduced body along
// the arm (reduction/mode_field.h). The marker's z axis is the tangent, so the generic joint's
// masks read naturally: translation along z and rotation about z are the sliding and the spin.
//
// Velocities (columns: the body's v = (R', omega, eta'), then s'):
//   r'   = R' - A u~ omega + A Phi_u eta' + A (t + Phi_u' eta) s'            (u = y + Phi_u eta)
//   e_a' = -A b_a~ omega - A g_a~ Phi_th eta' + A (g_a' + th x g_a' + (Phi_th' eta) x g_a) s'
//   omega_marker = A (omega + Phi_th eta' + (w + Phi_th' eta) s'),  w = (1/2) sum g_a x g_a'
// (b_a = g_a + th x g_a, th = Phi_th eta; linear in eta like every flexible marker).
//
// Beyond the ends: IDA's Newton iterates and a step that crosses an end (found by root finding
// and interpolated back to it) may ask for s a little outside [0, L]. There the curve and its
// section frame continue by their Taylor expansions at the end (the centre line to second order,
// the axes to first, so the velocity constraints stay continuous: a straight continuation would
// stop the frame's rotation at once, which no slider locked to it can follow), and the mode
// fields along their end slopes, up to overrun_fraction L; beyond that the evaluation throws
// (IDA then cuts the step). Results are never reported beyond an end: the run stops at it
// (Joint::limits()).
#pragma once

#include <geometry/section_frame.h>
#include <multibody/marker.h>
#include <reduction/mode_field.h>

#include <limits>
#include <memory>

namespace flextrack::multibody
{
class TrackMarker : public Marker
{
public:
  /// Fraction of the arm length that s may overrun an end during Newton iterations.
  static constexpr double overrun_fraction = 0.05;

  /// @p curve and @p frame in body axes; @p field: the arm's mode fields (null, or a body
  /// without modes: a rigid track). @p s0 [m] and @p s0_rate [m/s]: the contact's initial arc
  /// length and sliding speed.
  TrackMarker(const Body &body, std::string name, std::shared_ptr<const geometry::Curve> curve,
              std::shared_ptr<const geometry::SectionFrame> frame,
              std::shared_ptr<const reduction::ArmModeField> field, double s0, double s0_rate);

  unsigned int n_own_coordinates() const override { return 1; }
  void initial_own_coordinates(double *q, double *v) const override;
  void evaluate(const double *q, const double *own, MarkerKinematics &k) const override;
  bool modal_jacobian_derivatives(const double *q, const double *own,
                                  std::vector<ModalJacobianDerivative> &d) const override;
  double length() const { return curve->length(); }
  const geometry::Curve &track() const { return *curve; }

  /// The undeformed section axes (d2, d3, t) at @p s, body axes: columns.
  Matrix3 section_axes(double s) const;
  /// Marker axes = section axes times @p offset (a constant rotation, columns in section axes):
  /// a sleeve holds its second arm at a fixed angle to the first (identity by default).
  void set_axes_offset(const Matrix3 &offset) { axes_offset = offset; }

private:
  std::shared_ptr<const geometry::Curve> curve;
  std::shared_ptr<const geometry::SectionFrame> frame;
  std::shared_ptr<const reduction::ArmModeField> field;
  double s_start, s_rate;

  /// What evaluate() needs from the curve, the section frame and the mode fields at one arc
  /// length. A Jacobian by differences calls evaluate() once per perturbed coordinate, and all but
  /// the s column leave s unchanged: the last place is kept (the curve's arc-length inversion was
  /// a third of the laser robot's run time).
  struct Place
  {
    double s = std::numeric_limits<double>::quiet_NaN();
    geometry::CurveGeometry g;
    Vector3 d2, d2_s;
    std::vector<double> value, slope; ///< 6 x n mode fields and their s-derivatives
  };
  const Place &place_at(double s_on) const;
  /// The arc length on the track, within [0, L], and how far @p s is beyond an end (the overrun
  /// zone); throws where @p s is off the track.
  double clamped(double s, double &beyond) const;
  /// The marker's axes at the place (section axes times the offset, continued to first order
  /// beyond an end), their s-derivatives and, if asked, the section frame's Darboux vector.
  void marker_axes(const Place &place, double beyond, std::array<Vector3, 3> &axis, std::array<Vector3, 3> &axis_s,
                   Vector3 *darboux = nullptr) const;
  mutable Place last_place;
  Matrix3 axes_offset;
};
} // namespace flextrack::multibody
