// Export of a reduced body to MBDyn's modal joint: the modal element data file (.fem, MBDyn
// input manual, appendix "Modal Element Data / FEM File Format") and an include file (.elm)
// with a matching "joint: ..., modal, ..." statement.
//
// Record groups written: 1 (header), 2 (node labels), 5-7 (node coordinates), 8 (mode shapes at
// the exposed nodes), 9 (generalised mass), 10 (generalised stiffness), 12 (rigid-body inertia),
// 13 (generalised damping), 14-18 (inertia invariants I3, I4, I8, I5, I9 from the consistent
// mass matrix). Never 11 (lumped masses: MBDyn would add them to 14-18). Exposed nodes: the
// body's interfaces, labelled by their names. Layout rules (one comment line after the RG 1
// marker, none after the others, one header line before each mode, plain 'e' exponents with
// 17 significant digits, at most 6 numbers a line) are documented in doc/exports.md.
#pragma once

#include <reduction/reduced_body.h>

#include <string>

namespace flextrack::io
{
/// The .fem text. Throws InputError if the body's inertia tensor about its centre of mass is not
/// positive definite (MBDyn fails on its first step with such a body).
std::string mbdyn_fem_text(const reduction::ReducedBody &body);

/// The .elm text: a modal joint that reads @p fem_file_name, with one attachment per interface.
std::string mbdyn_elm_text(const reduction::ReducedBody &body, const std::string &fem_file_name);

/// Label of an interface in the .fem file: its name with blanks replaced by '_'.
std::string mbdyn_node_label(const std::string &interface_name);
} // namespace flextrack::io
