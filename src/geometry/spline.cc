#include <geometry/spline.h>
#include <base/input_error.h>

#include <algorithm>
#include <fstream>
#include <sstream>

namespace flextrack::geometry
{
std::vector<Point<3>> read_points(const std::string &file, const std::string &entry)
{
  std::ifstream in(file);
  if (!in)
    throw InputError(entry, "cannot open the points file '" + file + "'; give an existing, readable file");
  std::vector<Point<3>> points;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number)
    {
      line = line.substr(0, line.find('#'));
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream fields(line);
      Point<3> p;
      std::string rest;
      if (!(fields >> std::ws) || fields.eof())
        continue; // blank or comment line
      if (!(fields >> p[0] >> p[1] >> p[2]) || (fields >> rest))
        throw InputError(entry, "line " + std::to_string(number) + " of '" + file +
                         "' is not three numbers \"x y z\" [m]: '" + line + "'");
      points.push_back(p);
    }
  if (points.size() < 2)
    throw InputError(entry, "'" + file + "' holds " + std::to_string(points.size()) +
                     " points; a spline needs at least 2");
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i].distance(points[i - 1]) == 0)
      throw InputError(entry, "points " + std::to_string(i) + " and " + std::to_string(i + 1) + " of '" + file +
                       "' coincide; consecutive points must differ");
  return points;
}

std::shared_ptr<const Curve> make_spline_curve(const std::vector<Point<3>> &points)
{
  const std::size_t n = points.size() - 1; // number of segments
  std::vector<double> knot(n + 1, 0.0);
  for (std::size_t i = 1; i <= n; ++i)
    knot[i] = knot[i - 1] + points[i].distance(points[i - 1]);

  // Second derivatives m_i from the tridiagonal system of the natural spline (Thomas algorithm).
  std::vector<Vec3> m(n + 1);
  if (n >= 2)
    {
      std::vector<double> diag(n + 1, 0.0), upper(n + 1, 0.0);
      std::vector<Vec3> rhs(n + 1);
      for (std::size_t i = 1; i < n; ++i)
        {
          const double h0 = knot[i] - knot[i - 1], h1 = knot[i + 1] - knot[i];
          const double lower = h0 / 6;
          diag[i] = (h0 + h1) / 3;
          upper[i] = h1 / 6;
          rhs[i] = (points[i + 1] - points[i]) / h1 - (points[i] - points[i - 1]) / h0;
          if (i > 1)
            {
              const double f = lower / diag[i - 1];
              diag[i] -= f * upper[i - 1];
              rhs[i] -= f * rhs[i - 1];
            }
        }
      for (std::size_t i = n - 1; i >= 1; --i)
        {
          m[i] = (rhs[i] - (i + 1 < n ? upper[i] * m[i + 1] : Vec3())) / diag[i];
          if (i == 1) break;
        }
    }
  auto y = [points, knot, m, n](const Jet &p) {
    std::size_t i = std::upper_bound(knot.begin(), knot.end(), p.c[0]) - knot.begin();
    i = std::min(std::max<std::size_t>(i, 1), n) - 1;
    const double h = knot[i + 1] - knot[i];
    // Cubic on segment i in u = p - knot_i (exact jets: derivatives above 3 vanish).
    Jet u = p;
    u.c[0] -= knot[i];
    Jet3 r;
    for (int d = 0; d < 3; ++d)
      {
        const double a = points[i][d];
        const double b = (points[i + 1][d] - points[i][d]) / h - h * (2 * m[i][d] + m[i + 1][d]) / 6;
        const double c = m[i][d] / 2, e = (m[i + 1][d] - m[i][d]) / (6 * h);
        r[d] = Jet::constant(a) + u * (Jet::constant(b) + u * (Jet::constant(c) + e * u));
      }
    return r;
  };
  return std::make_shared<Curve>("spline through " + std::to_string(points.size()) + " points", y, 0.0,
                                 knot[n], false, knot);
}

std::shared_ptr<const Curve> make_spline_curve(const std::string &file, const std::string &entry)
{
  return make_spline_curve(read_points(file, entry));
}
} // namespace flextrack::geometry
