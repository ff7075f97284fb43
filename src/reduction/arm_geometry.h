// The exact geometry of a reduced body's arm, kept as parameter text so that a reduced body file
// alone puts a track on its arm: "subsection Curve" (the chosen kind) and "subsection Section
// frame" with the values the scene gave (fem::Arm::geometry_parameters; a spline's points inline).
// Reading it rebuilds the very same Curve and SectionFrame (the same code on the same numbers,
// so the same doubles), and the rebuilt curve is checked against the arm's stored node positions
// before anyone slides on it. The text comes from a file and is treated as untrusted.
#pragma once

#include <geometry/built_geometry.h>
#include <reduction/mode_field.h>

#include <cstddef>
#include <memory>
#include <string>

namespace flextrack::reduction
{
/// Longest geometry text [bytes]: a spline of the most points (100000) written inline at 17
/// digits is at most 7.3 MB; expressions are at most 10000 characters each.
constexpr std::size_t max_geometry_parameters_bytes = std::size_t(8) << 20;

/// A rebuilt arm's curve and section frame.
using ArmGeometry = geometry::CurveAndFrame;

/// The curve and section frame that @p text describes. Accepts only the curve and frame entries
/// (nothing else is declared), at most max_geometry_parameters_bytes, no "include", no line
/// continuation, no points file (the text must not reach outside itself). Throws
/// std::runtime_error saying what is wrong; the caller names the arm and the file.
ArmGeometry parse_arm_geometry(const std::string &text);

/// Allowed distance [m] of the rebuilt curve from the stored node positions: 1e-9 of the arm's
/// length plus 1e-12 of its largest coordinate (round-off of positions in double precision).
double arm_geometry_tolerance(const ArmModeData &arm);

/// Throws std::runtime_error unless @p curve is the centre line of @p arm's stored nodes: its
/// length is the last cell boundary, and its position at each node's arc length
/// s = cell_s[c] + xi[j] (cell_s[c+1] - cell_s[c]) is the stored position, both within
/// arm_geometry_tolerance(). The message gives the largest distance, where, and the tolerance.
void check_arm_geometry(const geometry::Curve &curve, const ArmModeData &arm);

/// Sets arm.curve and arm.frame from arm.geometry_parameters and checks the curve against the
/// stored nodes (parse_arm_geometry, check_arm_geometry).
void rebuild_arm_geometry(ArmModeData &arm);

/// For contacts that slide on the arm (track joints): throws std::runtime_error naming the arm
/// when the reduced body does not know its curve and section frame (an arm built in code, not
/// read from a parameter file).
void require_arm_geometry(const ArmModeData &arm);
} // namespace flextrack::reduction
