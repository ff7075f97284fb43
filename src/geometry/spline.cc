#include <geometry/spline.h>
#include <base/input_error.h>
#include <base/names.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace flextrack::geometry
{
std::vector<Point<3>> read_points(const std::string &file, const std::string &entry)
{
  const std::string name = base::printable_excerpt(file);
  std::error_code error;
  if (!std::filesystem::exists(file, error))
    throw InputError(entry, "cannot open the points file '" + name + "': it does not exist; give an existing, readable file");
  if (!std::filesystem::is_regular_file(file, error))
    throw InputError(entry, "the points file '" + name + "' is not a regular file (a directory or a device?)");
  if (const auto size = std::filesystem::file_size(file, error); !error && size > max_points_file_bytes)
    throw InputError(entry, "the points file '" + name + "' has " + std::to_string(size) + " bytes; at most " +
                              std::to_string(max_points_file_bytes >> 20) + " MiB are allowed");
  std::ifstream in(file);
  if (!in)
    throw InputError(entry, "cannot open the points file '" + name + "'; give an existing, readable file");
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
      const std::string where = "line " + std::to_string(number) + " of '" + name + "'";
      if (!(fields >> p[0] >> p[1] >> p[2]) || (fields >> rest))
        throw InputError(entry, where + " is not three numbers \"x y z\" [m]: '" + base::printable_excerpt(line) + "'");
      for (int d = 0; d < 3; ++d)
        if (!(std::abs(p[d]) <= max_coordinate))
          {
            std::ostringstream m;
            m << where << ": coordinate " << p[d] << " m; allowed: finite coordinates of at most " << max_coordinate
              << " m in size";
            throw InputError(entry, m.str());
          }
      if (points.size() == max_spline_points)
        throw InputError(entry, "'" + name + "' holds more than " + std::to_string(max_spline_points) +
                                  " points; at most " + std::to_string(max_spline_points) +
                                  " are allowed (a cubic spline needs far fewer: thin the points)");
      points.push_back(p);
    }
  if (points.size() < 2)
    throw InputError(entry, "'" + name + "' holds " + std::to_string(points.size()) +
                     " points; a spline needs at least 2");
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i].distance(points[i - 1]) == 0)
      throw InputError(entry, "points " + std::to_string(i) + " and " + std::to_string(i + 1) + " of '" + name +
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
  // Segment i is the cubic a + b u + c u^2 + e u^3 in u = p - knot_i, per coordinate; its
  // coefficients are computed once here, not at every evaluation.
  std::vector<std::array<double, 12>> cubic(n);
  for (std::size_t i = 0; i < n; ++i)
    {
      const double h = knot[i + 1] - knot[i];
      for (int d = 0; d < 3; ++d)
        {
          cubic[i][4 * d + 0] = points[i][d];
          cubic[i][4 * d + 1] = (points[i + 1][d] - points[i][d]) / h - h * (2 * m[i][d] + m[i + 1][d]) / 6;
          cubic[i][4 * d + 2] = m[i][d] / 2;
          cubic[i][4 * d + 3] = (m[i + 1][d] - m[i][d]) / (6 * h);
        }
    }
  auto y = [knot, cubic, n](const Jet &p) {
    std::size_t i = std::upper_bound(knot.begin(), knot.end(), p.c[0]) - knot.begin();
    i = std::min(std::max<std::size_t>(i, 1), n) - 1;
    const double u = p.c[0] - knot[i];
    // The cubic's Taylor coefficients at u (exact: those above order 3 vanish), composed with
    // the argument's jet; a plain variable (the common case) needs no composition.
    const bool plain = p.c[1] == 1 && p.c[2] == 0 && p.c[3] == 0 && p.c[4] == 0;
    Jet3 r;
    for (int d = 0; d < 3; ++d)
      {
        const double a = cubic[i][4 * d], b = cubic[i][4 * d + 1], c = cubic[i][4 * d + 2], e = cubic[i][4 * d + 3];
        Jet f;
        f.c[0] = a + u * (b + u * (c + u * e));
        f.c[1] = b + u * (2 * c + 3 * e * u);
        f.c[2] = c + 3 * e * u;
        f.c[3] = e;
        r[d] = plain ? f : compose(f, p);
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
