// A small flexible body for the multibody unit tests: a curved arm (arc of radius 0.4 m over
// 1.5 rad, rectangle 30 x 20 mm of the default material, 8 elements) with interfaces 'root' (s = 0) and 'tip'
// (s = 0.6 m), a point mass at the tip, free-interface basis of 5 normal modes, 2 % modal damping.
#pragma once

#include <fem/body_model.h>
#include <io/body_scene.h>
#include <reduction/component_modes.h>
#include <reduction/reduced_body_builder.h>

#include <memory>
#include <string>

namespace flextrack::test
{
inline std::shared_ptr<const reduction::ReducedBody> curved_arm(const bool geometric_stiffness)
{
  const std::string text =
    "set Model = body\nsubsection Body\n set Solid = false\n set Arms = arc\n"
    " set Interfaces = root: arm arc at 0; tip: arm arc at 0.6\n set Point masses = tip: 0.3, 2e-5, 3e-5, 4e-5\nend\n"
    "subsection Arm arc\n subsection Curve\n  set Kind = arc\n  subsection Arc\n   set Radius = 0.4\n"
    "   set Angle = 1.5\n  end\n end\n subsection Cross section\n  set Shape = rectangle\n  set Width = 0.03\n"
    "  set Height = 0.02\n end\n subsection Mesh\n  set Number of elements = 8\n end\nend\n"
    "subsection Reduction\n set Method = free interface\n set Number of normal modes = 5\n"
    " set Damping ratio = 0.02\n set Geometric stiffness = " +
    std::string(geometric_stiffness ? "true" : "false") + "\nend\n";
  const auto scene = io::read_body_scene_from_string(text);
  const fem::BodyModel model(scene.body);
  return std::make_shared<reduction::ReducedBody>(
    reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), scene.reduction.method_name()));
}
} // namespace flextrack::test
