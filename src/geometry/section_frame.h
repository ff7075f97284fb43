// Orientation of the beam cross-section along a curve: the section's y axis d2(s) (unit,
// normal to the tangent); z = tangent x y. Three choices:
//  - frenet: d2 = principal normal (the seed's choice); undefined where the curvature vanishes;
//  - rotation minimising: d2 parallel-transported from its start value (no twist about the
//    tangent), computed by the double-reflection method (Wang et al., ACM TOG 27(1), 2008) on
//    4096 steps, 4th order accurate;
//  - fixed vector: d2 = the user's reference vector projected onto the section plane.
#pragma once

#include <geometry/curve.h>
#include <geometry/curve_library.h>

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <vector>

namespace flextrack::geometry
{
class SectionFrame
{
public:
  enum class Kind { frenet, rotation_minimising, fixed_vector };

  SectionFrame(std::shared_ptr<const Curve> curve, Kind kind, const Vec3 &reference);

  /// Section y axis d2 at arc length s (unit, orthogonal to the tangent).
  Vec3 y_axis(double s) const;
  /// The same at the point of @p g (= curve geometry at g.s), without evaluating the curve again.
  Vec3 y_axis(const CurveGeometry &g) const;
  /// d(d2)/ds [1/m] at the point of @p g, where the y axis is @p y (= y_axis(g.s)), for a contact
  /// sliding along the arm: Frenet n' = -k t + tau b; rotation minimising -(d2 . t') t (no twist
  /// about the tangent, by definition); fixed vector the derivative of the normalised projection.
  Vec3 y_axis_rate(const CurveGeometry &g, const Vec3 &y) const;
  Kind kind() const { return frame_kind; }

  static void declare_parameters(dealii::ParameterHandler &prm);
  static SectionFrame parse_parameters(dealii::ParameterHandler &prm, std::shared_ptr<const Curve> curve,
                                       const ParseContext &where);

private:
  std::shared_ptr<const Curve> curve;
  Kind frame_kind;
  Vec3 reference;
  std::vector<Vec3> rmf_y; // rotation-minimising frame at s_i = i L / N
  std::vector<Point<3>> rmf_x; // the curve's points and tangents there (each y_axis(s) starts
  std::vector<Vec3> rmf_t;     // from the nearest: no second curve evaluation)
};

/// The frame is undefined (Frenet at zero curvature, reference parallel to the tangent).
class FrameError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};
} // namespace flextrack::geometry
