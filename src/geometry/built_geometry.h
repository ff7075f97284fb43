// The curves and section frames this process has built, by the parameter text that describes
// them (fem::Arm's geometry_parameters: the Curve subsection, the chosen kind only, and the
// section frame entries). A curve and its frame take tens of milliseconds to build (the arc-length
// table, the checks of parse_curve, the frame's transport) and are immutable, and the same text
// is built again and again: a run builds each arm from its body scene and rebuilds it from the
// cached reduced body's stored text; the rigid reference run and every case of a study do the
// same. Thread safe; at most 64 texts are kept.
#pragma once

#include <geometry/curve.h>
#include <geometry/section_frame.h>

#include <memory>
#include <optional>
#include <string>

namespace flextrack::geometry
{
struct CurveAndFrame
{
  std::shared_ptr<const Curve> curve;
  std::shared_ptr<const SectionFrame> frame;
};

/// The curve and frame built before from @p text, if any.
std::optional<CurveAndFrame> built_geometry(const std::string &text);
/// Keeps @p geometry, built from @p text (only a geometry that was built without error).
void remember_built_geometry(const std::string &text, const CurveAndFrame &geometry);
} // namespace flextrack::geometry
