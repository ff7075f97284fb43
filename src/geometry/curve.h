// A smooth spatial curve y(s), parametrised by arc length s in [0, L] (metres).
//
// Curves come in two forms (seed eq. 44): type II is given in arc length directly; type I in a
// general parameter t, which is converted numerically: s(t) = int |dy/dt| dt, tabulated once by
// adaptive Gauss-Legendre quadrature to ~1e-15 relative accuracy (or, where the parameter values
// are large, to the rounding error that representing t itself implies), and inverted by
// safeguarded Newton's method. The table holds at most max_arc_length_panels panels: a curve
// whose arc length does not converge within them (a pole, a cusp, an oscillation faster than the
// quadrature resolves) is refused with a CurveError instead of running for hours. Derivatives with respect to s come from Taylor jets, so curvature, torsion and their
// derivatives are exact up to rounding for any curvature (no small-curvature linearisation).
#pragma once

#include <geometry/taylor.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace flextrack::geometry
{
using dealii::Point;
using Vec3 = dealii::Tensor<1, 3>;

/// Largest coordinate and largest length of a centre line [m]: a curve beyond them is refused
/// as absurd (an expression across its pole, a unit mistake) before it reaches the FE model.
constexpr double max_coordinate = 1e6;
constexpr double max_curve_length = 1e6;

/// Most panels in the arc-length table of a type I curve (each is 4 doubles: 32 MiB).
constexpr std::size_t max_arc_length_panels = std::size_t(1) << 20;

/// A curve that cannot be built: empty parameter range, arc length not finite or not
/// converging. what() says what is wrong; the caller names the entry.
class CurveError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// The curve's position as jets in its own parameter: y(parameter) with derivatives.
using CurveFunction = std::function<Jet3(const Jet &parameter)>;
/// dy/dp at a parameter value: optional, a cheaper way to the speed |y'(p)| that the arc-length
/// quadrature of a type I curve evaluates thousands of times (it must equal the first
/// derivative of the CurveFunction; without it, that derivative is taken from the jets).
using CurveVelocity = std::function<Vec3(double parameter)>;

/// Differential geometry of the centre line at one arc length s.
struct CurveGeometry
{
  double s = 0;
  Point<3> position;
  Vec3 tangent;                      ///< y'(s), unit
  std::array<Vec3, 4> derivative;    ///< y^(k+1)(s) for k = 0..3 (derivative[0] = tangent)
  double curvature = 0;              ///< k = |y''|, 1/m
  double curvature_rate = 0;         ///< dk/ds, 1/m^2
  double torsion = 0;                ///< tau, 1/m (0 where k = 0)
  double torsion_rate = 0;           ///< dtau/ds, 1/m^2
  Vec3 normal;                       ///< Frenet principal normal y''/k (zero where k = 0)
  Vec3 binormal;                     ///< tangent x normal (zero where k = 0)
};

class Curve
{
public:
  /// @p y: the curve on jets of its parameter p in [p_begin, p_end]. When
  /// @p parameter_is_arc_length is false (type I), arc length is computed numerically.
  /// @p breakpoints: parameter values where higher derivatives jump (spline knots).
  /// @p velocity: dy/dp, see CurveVelocity. Throws CurveError (see above).
  Curve(std::string description, CurveFunction y, double p_begin, double p_end,
        bool parameter_is_arc_length, std::vector<double> breakpoints = {}, CurveVelocity velocity = {});

  double length() const { return total_length; }
  /// True if the end point coincides with the start point (a ring).
  bool is_closed() const { return closed; }
  const std::string &description() const { return name; }

  Point<3> position(double s) const;
  /// Jets of the coordinates in arc length around s: derivatives with respect to s.
  Jet3 arc_length_jet(double s) const;
  CurveGeometry geometry(double s) const;

  /// Type I conversion: parameter value at arc length s, and arc length at parameter p.
  double parameter_at(double s) const;
  double arc_length_at(double p) const;

private:
  double speed(double p) const;
  double gauss_integral(double a, double b) const; // int_a^b |y'(p)| dp, 10-point Gauss
  void tabulate_arc_length(const std::vector<double> &breakpoints);
  void add_panel(double a, double b, double integral, int depth);
  /// Chebyshev series of each panel's speed and arc length (see tabulate_series).
  void tabulate_series();
  /// int_{p_i}^p |y'| and |y'(p)| on panel i: from its series where it has one, else by Gauss.
  double panel_arc_length(std::size_t i, double p) const;
  double panel_speed(std::size_t i, double p) const;

  std::string name;
  CurveFunction function;
  CurveVelocity velocity;
  double p0, p1;
  bool arc_length_parameter;
  // Type I table: panel ends p_table[i] with arc lengths s_table[i].
  std::vector<double> p_table, s_table;
  // Per panel i: the speed's Chebyshev coefficients (series_points of them) and the arc length's
  // from p_table[i] (one more), at series_stride * i; has_series[i] is false where the series did
  // not reproduce the panel (then Gauss is used there).
  static constexpr unsigned int series_points = 16, series_stride = 2 * series_points + 1;
  /// Series for at most this many panels (33 doubles each: 17 MiB); a table beyond it (a curve
  /// that is hardly smooth) uses Gauss throughout.
  static constexpr std::size_t max_series_panels = std::size_t(1) << 16;
  std::vector<double> series;
  std::vector<char> has_series;
  double total_length = 0;
  bool closed = false;
};
} // namespace flextrack::geometry
