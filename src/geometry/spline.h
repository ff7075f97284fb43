// A smooth curve through points read from a file: natural cubic spline in chord length.
//
// Limits: a points file is a regular file of at most max_points_file_bytes, holding 2 to
// max_spline_points points whose coordinates are finite and at most max_coordinate [m] in size.
// Building the spline and its arc-length table is linear in the number of points.
#pragma once

#include <geometry/curve.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::geometry
{
constexpr std::size_t max_spline_points = 100000;
constexpr std::size_t max_points_file_bytes = std::size_t(64) << 20; // 64 MiB

/// Read points (one "x y z" per line) from @p file; @p entry names the parameter for errors.
std::vector<Point<3>> read_points(const std::string &file, const std::string &entry);

/// The natural cubic spline (zero second derivative at both ends) through @p points,
/// parametrised by cumulative chord length; a type I curve (arc length is computed).
std::shared_ptr<const Curve> make_spline_curve(const std::vector<Point<3>> &points);
std::shared_ptr<const Curve> make_spline_curve(const std::string &file, const std::string &entry);
} // namespace flextrack::geometry
