#include <geometry/curve.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace flextrack::geometry
{
namespace
{
// 10-point Gauss-Legendre rule on [-1, 1] (nodes symmetric about 0).
constexpr double gl_x[5] = {0.1488743389816312, 0.4333953941292472, 0.6794095682990244,
                            0.8650633666889845, 0.9739065285171717};
constexpr double gl_w[5] = {0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
                            0.1494513491505806, 0.0666713443086881};

Vec3 coefficient(const Jet3 &y, const int k) { return Vec3({y[0].c[k], y[1].c[k], y[2].c[k]}); }
Vec3 derivative(const Jet3 &y, const int k)
{
  return Vec3({y[0].derivative(k), y[1].derivative(k), y[2].derivative(k)});
}
} // namespace

Curve::Curve(std::string description, CurveFunction y, const double p_begin, const double p_end,
             const bool parameter_is_arc_length, std::vector<double> breakpoints, CurveVelocity dy_dp)
  : name(std::move(description)), function(std::move(y)), velocity(std::move(dy_dp)), p0(p_begin), p1(p_end),
    arc_length_parameter(parameter_is_arc_length)
{
  if (!(p1 > p0) || !std::isfinite(p1 - p0))
    throw CurveError("the parameter range of the " + name + " is empty or not finite");
  if (arc_length_parameter)
    total_length = p1 - p0;
  else
    tabulate_arc_length(breakpoints);
  const double gap = (position(total_length) - position(0.0)).norm();
  closed = total_length > 0 && gap <= 1e-10 * total_length;
}

double Curve::speed(const double p) const
{
  if (velocity) return velocity(p).norm();
  const Jet3 y = function(Jet::variable(p));
  return coefficient(y, 1).norm();
}

double Curve::gauss_integral(const double a, const double b) const
{
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0;
  for (int i = 0; i < 5; ++i)
    sum += gl_w[i] * (speed(mid - half * gl_x[i]) + speed(mid + half * gl_x[i]));
  return half * sum;
}

void Curve::tabulate_arc_length(const std::vector<double> &breakpoints)
{
  // Panels: at least 64 over the range, and every breakpoint is a panel end so that the
  // integrand is smooth inside each panel. Each panel is then bisected until two Gauss
  // rules agree (see add_panel).
  std::vector<double> ends = {p0, p1};
  for (const double b : breakpoints)
    if (b > p0 && b < p1) ends.push_back(b);
  std::sort(ends.begin(), ends.end());
  p_table = {p0};
  s_table = {0.0};
  for (std::size_t k = 0; k + 1 < ends.size(); ++k)
    {
      const int n = std::max(1, static_cast<int>(std::ceil(64 * (ends[k + 1] - ends[k]) / (p1 - p0))));
      for (int i = 0; i < n; ++i)
        {
          const double a = ends[k] + (ends[k + 1] - ends[k]) * i / n;
          const double b = ends[k] + (ends[k + 1] - ends[k]) * (i + 1) / n;
          add_panel(a, b, gauss_integral(a, b), 0);
        }
    }
  total_length = s_table.back();
  if (!std::isfinite(total_length))
    throw CurveError("the arc length of the " + name + " is not finite (a pole or an overflow of the coordinates)");
  tabulate_series();
}

namespace
{
/// Clenshaw's sum c_0 / 2 + sum_{j >= 1} c_j T_j(x) of n coefficients.
double chebyshev_sum(const double *c, const unsigned int n, const double x)
{
  double b1 = 0, b2 = 0;
  for (unsigned int j = n - 1; j >= 1; --j)
    {
      const double b0 = 2 * x * b1 - b2 + c[j];
      b2 = b1;
      b1 = b0;
    }
  return x * b1 - b2 + 0.5 * c[0];
}
} // namespace

void Curve::tabulate_series()
{
  // Why: converting s to p (every track contact, every residual) integrated the speed by Gauss
  // from the panel start, 11 evaluations of the curve per Newton step: 6 % of the laser robot's
  // run. The speed on each panel is interpolated at 16 Chebyshev points instead and the series
  // integrated term by term (e.g. Trefethen, Approximation Theory and Approximation Practice,
  // ch. 3 and 19); the arc length and speed then cost a Clenshaw sum each. A panel keeps its
  // series only if the series' last two speed coefficients are below 1e-14 of the largest and the
  // integrated series reproduces the panel's adaptive Gauss length to 1e-14 (or the rounding
  // floor of add_panel): elsewhere Gauss is used as before.
  constexpr unsigned int n = series_points;
  const std::size_t panels = p_table.size() - 1;
  has_series.assign(panels, 0);
  if (panels > max_series_panels) return;
  series.assign(series_stride * panels, 0.0);
  double f[n], cosines[n][n]; // cosines[j][k] = cos(pi j (k + 1/2) / n) = T_j at node k
  for (unsigned int j = 0; j < n; ++j)
    for (unsigned int k = 0; k < n; ++k) cosines[j][k] = std::cos(M_PI * j * (k + 0.5) / n);
  for (std::size_t i = 0; i < panels; ++i)
    {
      const double a = p_table[i], b = p_table[i + 1], half = 0.5 * (b - a), mid = 0.5 * (a + b);
      for (unsigned int k = 0; k < n; ++k)
        f[k] = speed(mid + half * cosines[1][k]);
      double *c = &series[series_stride * i], *C = c + n, largest = 0;
      for (unsigned int j = 0; j < n; ++j)
        {
          double sum = 0;
          for (unsigned int k = 0; k < n; ++k) sum += f[k] * cosines[j][k];
          c[j] = 2.0 / n * sum;
          largest = std::max(largest, std::abs(c[j]));
        }
      // d/dx sum C_j T_j = half * speed: C_j = half (c_{j-1} - c_{j+1}) / (2 j), C_0 so that the
      // sum is 0 at x = -1 (T_j(-1) = (-1)^j).
      double at_start = 0;
      for (unsigned int j = 1; j <= n; ++j)
        {
          const double next = j + 1 < n ? c[j + 1] : 0.0, previous = j - 1 < n ? c[j - 1] : 0.0;
          C[j] = half * (previous - next) / (2.0 * j);
          at_start += (j % 2 ? -1 : 1) * C[j];
        }
      C[0] = -2 * at_start;
      // The panel's own Gauss length: s_table's differences carry the running sum's rounding
      // (1e-16 of s), more than 1e-14 of a panel once there are a few hundred of them.
      const double length = gauss_integral(a, b);
      const double rounding_floor = 16 * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b)) *
                                    std::abs(length) / (b - a);
      const bool converged = std::abs(c[n - 1]) <= 1e-14 * largest && std::abs(c[n - 2]) <= 1e-14 * largest;
      const bool reproduces = std::abs(chebyshev_sum(C, n + 1, 1.0) - length) <=
                              std::max(1e-14 * std::abs(length), rounding_floor);
      has_series[i] = converged && reproduces && std::isfinite(largest);
    }
}

double Curve::panel_arc_length(const std::size_t i, const double p) const
{
  const double a = p_table[i], b = p_table[i + 1];
  if (!has_series[i] || !(p >= a && p <= b)) return gauss_integral(a, p); // outside: as before
  const double x = std::clamp((2 * p - a - b) / (b - a), -1.0, 1.0);
  return chebyshev_sum(&series[series_stride * i + series_points], series_points + 1, x);
}

double Curve::panel_speed(const std::size_t i, const double p) const
{
  const double a = p_table[i], b = p_table[i + 1];
  if (!has_series[i] || !(p >= a && p <= b)) return speed(p);
  const double x = std::clamp((2 * p - a - b) / (b - a), -1.0, 1.0);
  return chebyshev_sum(&series[series_stride * i], series_points, x);
}

void Curve::add_panel(const double a, const double b, const double integral, const int depth)
{
  // Accept when the two rules agree to 1e-15 relative, or to the rounding floor: the Gauss
  // nodes themselves are only known to eps |p|, which moves the arc length of a panel by about
  // eps |p| times the mean speed. Below that floor a smooth panel only looks unconverged
  // (a spline through 2000 scattered points, whose knots reach p ~ 1e3, otherwise bisected
  // into 2e7 panels).
  const double m = 0.5 * (a + b);
  const double left = gauss_integral(a, m), right = gauss_integral(m, b);
  const double rounding_floor = 16 * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b)) *
                       std::abs(integral) / (b - a);
  const double tolerance = std::max(1e-15 * std::max(integral, 1e-300), rounding_floor);
  if (depth < 30 && std::abs(left + right - integral) > tolerance)
    {
      if (p_table.size() > 2 * max_arc_length_panels)
        throw CurveError("the arc length of the " + name + " does not converge within " +
                         std::to_string(max_arc_length_panels) + " quadrature panels; the curve is not smooth "
                         "enough (a pole, a cusp or a rapid oscillation)");
      add_panel(a, m, left, depth + 1);
      add_panel(m, b, right, depth + 1);
      return;
    }
  p_table.push_back(m);
  s_table.push_back(s_table.back() + left);
  p_table.push_back(b);
  s_table.push_back(s_table.back() + right);
}

double Curve::arc_length_at(const double p) const
{
  if (arc_length_parameter)
    return p - p0;
  const auto it = std::upper_bound(p_table.begin(), p_table.end(), p);
  const std::size_t i = it == p_table.begin() ? 0 : std::min<std::size_t>(it - p_table.begin() - 1, p_table.size() - 2);
  return s_table[i] + panel_arc_length(i, p);
}

double Curve::parameter_at(const double s) const
{
  if (arc_length_parameter)
    return p0 + s;
  const auto it = std::upper_bound(s_table.begin(), s_table.end(), s);
  const std::size_t i = it == s_table.begin() ? 0 : std::min<std::size_t>(it - s_table.begin() - 1, s_table.size() - 2);
  // Newton's method on f(p) = s_i + int_{p_i}^p |y'| - s = 0, started from the linear guess and
  // kept inside the bracket [p_i, p_i+1] (f is monotone there): a step that leaves it, or a zero
  // speed (a cusp), bisects instead.
  double lo = p_table[i], hi = p_table[i + 1];
  const double ds = s_table[i + 1] - s_table[i];
  double p = ds > 0 ? std::clamp(lo + (s - s_table[i]) / ds * (hi - lo), lo, hi) : lo;
  for (int iteration = 0; iteration < 100; ++iteration)
    {
      const double residual = s_table[i] + panel_arc_length(i, p) - s;
      if (residual == 0) break;
      (residual > 0 ? hi : lo) = p;
      const double v = panel_speed(i, p);
      double next = v > 0 ? p - residual / v : 0.5 * (lo + hi);
      if (!(next >= lo && next <= hi)) next = 0.5 * (lo + hi);
      const double step = next - p;
      p = next;
      if (std::abs(step) <= 1e-15 * (std::abs(p) + (p1 - p0)))
        break;
    }
  return p;
}

Jet3 Curve::arc_length_jet(const double s) const
{
  if (arc_length_parameter)
    return function(Jet::variable(p0 + s));
  // y(p(s)): expand y and s(p) around p(s), revert s(p) to p(s), compose.
  const double p = parameter_at(s);
  const Jet pj = Jet::variable(p);
  const Jet3 y = function(pj);
  Jet speed_jet;
  {
    // |y'(p)| as a jet: y'(p) has coefficients (k+1) c_{k+1} of y.
    Jet3 dy;
    for (int d = 0; d < 3; ++d)
      for (int k = 0; k < jet_order; ++k)
        dy[d].c[k] = (k + 1) * y[d].c[k + 1];
    speed_jet = sqrt(dy[0] * dy[0] + dy[1] * dy[1] + dy[2] * dy[2]);
  }
  Jet s_of_p; // s(p + h) - s(p) = int speed: coefficients speed_{k-1} / k
  for (int k = 1; k <= jet_order; ++k)
    s_of_p.c[k] = speed_jet.c[k - 1] / k;
  const Jet p_of_s = invert(s_of_p, p);
  Jet3 result;
  for (int d = 0; d < 3; ++d)
    result[d] = compose(y[d], p_of_s);
  return result;
}

Point<3> Curve::position(const double s) const
{
  const Jet3 y = arc_length_parameter ? function(Jet::constant(p0 + s))
                                      : function(Jet::constant(parameter_at(s)));
  return Point<3>(y[0].c[0], y[1].c[0], y[2].c[0]);
}

CurveGeometry Curve::geometry(const double s) const
{
  const Jet3 y = arc_length_jet(s);
  CurveGeometry g;
  g.s = s;
  g.position = Point<3>(y[0].c[0], y[1].c[0], y[2].c[0]);
  for (int k = 0; k < 4; ++k)
    g.derivative[k] = derivative(y, k + 1);
  // Rounding leaves |y'| = 1 only to ~1e-15; normalise so frames are orthonormal.
  g.tangent = g.derivative[0] / g.derivative[0].norm();
  const Vec3 &d2 = g.derivative[1], &d3 = g.derivative[2], &d4 = g.derivative[3];
  g.curvature = d2.norm();
  if (g.curvature > 1e-12 / std::max(total_length, 1e-300))
    {
      const double k = g.curvature;
      const Vec3 t_x_d2 = dealii::cross_product_3d(g.tangent, d2);
      g.curvature_rate = d2 * d3 / k;
      g.torsion = t_x_d2 * d3 / (k * k);
      g.torsion_rate = t_x_d2 * d4 / (k * k) - 2.0 * g.torsion * g.curvature_rate / k;
      g.normal = (d2 - (d2 * g.tangent) * g.tangent);
      g.normal /= g.normal.norm();
      g.binormal = dealii::cross_product_3d(g.tangent, g.normal);
    }
  return g;
}
} // namespace flextrack::geometry
