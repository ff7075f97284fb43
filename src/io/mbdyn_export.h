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
//
// Record groups 9, 10 and 13 hold the symmetric part of each reduced matrix, exactly symmetric
// (MBDyn compares M(i, j) with M(j, i) bit for bit and warns on any difference). When the basis
// is mass-orthonormal, off-diagonal terms at round-off level are written as 0 (MBDyn also warns
// on any non-zero off-diagonal term): see mbdyn_round_off_threshold.
//
// The .elm statement follows the modal joint syntax of the MBDyn input manual (section "Modal",
// joints), token by token: node, mode count, 'from file' (FEM node count from the .fem file),
// 'damping from file' (record group 13), the file name, the interface count, the interfaces.
// A body whose data show supports gets a clamp of its modal node (see MbdynSupport), unless
// the export is asked otherwise (MbdynClamp: 'flextrack export --mbdyn-clamp no' for a body that
// hangs on a joint of the including model; MBDyn's input has no conditional statements, so the
// choice is made when the file is written, not by a 'set:' variable).
#pragma once

#include <reduction/reduced_body.h>

#include <string>
#include <utility>
#include <vector>

namespace flextrack::io
{
/// A basis counts as mass-orthonormal when every entry of M - 1 is at most this in magnitude.
inline constexpr double mbdyn_orthonormal_tolerance = 1e-9;
/// With a mass-orthonormal basis, an off-diagonal term A(i, j) of the mass, stiffness or damping
/// matrix is written as 0 when |A(i, j)| <= mbdyn_round_off_threshold * sqrt(|A(i, i) A(j, j)|).
/// In the scaled matrix D^-1/2 A D^-1/2 (D the diagonal) this drops terms of at most 1e-9: each
/// eigenvalue (w^2) moves by at most about (n - 1) 1e-9 relative (the scaled matrix is near the
/// identity), by O(1e-18) for modes that are not nearly repeated. Measured round-off in
/// FlexTrack's bases (at most 1.3e-11, prm/curved_boom_body.prm): see doc/exports.md.
inline constexpr double mbdyn_round_off_threshold = 1e-9;

/// The generalised mass, stiffness and damping as written to record groups 9, 10 and 13.
struct MbdynMatrices
{
  dealii::FullMatrix<double> mass, stiffness, damping;
  bool mass_orthonormal = false; ///< round-off off-diagonal terms were set to 0
};
/// The symmetric part (A + A^T) / 2 of each matrix, computed once per pair so that A(i, j) and
/// A(j, i) are the same double; with a mass-orthonormal basis, off-diagonal round-off set to 0.
MbdynMatrices mbdyn_matrices(const reduction::ReducedBody &body);

/// What the data of a reduced body show about how it is held. A free body always carries one of
/// two signatures (the reduction builds it so): Craig-Bampton holds it at its first interface
/// (every mode is exactly 0 there), free-interface uses mean axes (I3 = I4 = 0 to round-off).
/// A body with modes and neither signature has supports. Without modes, or with a signature
/// (a supported body whose first interface sits on its supports looks the same), it is not
/// known.
enum class MbdynSupport
{
  supported,               ///< the .elm clamps the modal node
  free_at_first_interface, ///< Craig-Bampton, body frame at the first interface
  free_mean_axes,          ///< free-interface method, mean axes
  no_modes                 ///< a rigid body: nothing shows supports
};
MbdynSupport mbdyn_support(const reduction::ReducedBody &body);

/// Whether the .elm clamps the modal node (flextrack export --mbdyn-clamp).
enum class MbdynClamp
{
  automatic, ///< "auto", the default: clamped when the data show supports (MbdynSupport::supported)
  yes,       ///< always clamped where it stands (a body held at its first interface, say)
  no         ///< never: the including model holds the modal node by its own joint (a pendulum)
};
/// "auto, yes, no", for messages.
std::string mbdyn_clamp_names();
/// The setting called @p name; InputError naming @p entry and the allowed names if none is.
MbdynClamp mbdyn_clamp_from_name(const std::string &name, const std::string &entry);

/// The .fem text. Throws InputError if the body's inertia tensor about its centre of mass is not
/// positive definite (MBDyn fails on its first step with such a body).
std::string mbdyn_fem_text(const reduction::ReducedBody &body);

/// The .elm text: a modal joint that reads @p fem_file_name, with one attachment per interface,
/// and a clamp of the modal node as @p clamp says (automatic: for a supported body; otherwise a
/// comment saying when to add one, or, with 'no' on a supported body, how to hold it). Throws
/// InputError if @p fem_file_name cannot be written inside an MBDyn string.
std::string mbdyn_elm_text(const reduction::ReducedBody &body, const std::string &fem_file_name,
                           MbdynClamp clamp = MbdynClamp::automatic);

/// (file name, text) of STEM.fem and STEM.elm, the .elm written with @p clamp.
std::vector<std::pair<std::string, std::string>> mbdyn_export_files(const reduction::ReducedBody &body,
                                                                    const std::string &stem, MbdynClamp clamp);

/// Label of an interface in the .fem file: its name with blanks replaced by '_'.
std::string mbdyn_node_label(const std::string &interface_name);
} // namespace flextrack::io
