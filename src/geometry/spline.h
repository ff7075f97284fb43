// A smooth curve through points read from a file: natural cubic spline in chord length.
#pragma once

#include <geometry/curve.h>

#include <memory>
#include <string>
#include <vector>

namespace flextrack::geometry
{
/// Read points (one "x y z" per line) from @p file; @p entry names the parameter for errors.
std::vector<Point<3>> read_points(const std::string &file, const std::string &entry);

/// The natural cubic spline (zero second derivative at both ends) through @p points,
/// parametrised by cumulative chord length; a type I curve (arc length is computed).
std::shared_ptr<const Curve> make_spline_curve(const std::vector<Point<3>> &points);
std::shared_ptr<const Curve> make_spline_curve(const std::string &file, const std::string &entry);
} // namespace flextrack::geometry
