// Mode shapes of a reduced body as one VTK XML unstructured grid (.vtu), ASCII, Float64 with 17
// significant digits (read back exactly by ParaView, meshio and VTK): the body's drawing surface
// (quadratic quadrilaterals of the solid's boundary, VTK type 23; arm centre-line segments, type
// 3) and one 3-component point array per mode, "mode_001", ... [m per unit modal coordinate],
// plus a field array "frequencies_Hz".
#pragma once

#include <reduction/reduced_body.h>

#include <string>

namespace flextrack::io
{
std::string mode_shapes_vtu_text(const reduction::ReducedBody &body);
} // namespace flextrack::io
