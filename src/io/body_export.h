// Exports of a reduced body for other tools, written all-or-nothing: every file goes to a
// temporary name first and is renamed only when all of them are complete.
//   mbdyn: STEM.fem (modal element data) and STEM.elm (a modal joint statement to include)
//   vtu:   STEM_modes.vtu (mode shapes on the body's surface, Float64; ParaView, meshio)
#pragma once

#include <reduction/reduced_body.h>

#include <string>
#include <vector>

namespace flextrack::io
{
/// The formats export_reduced_body knows: mbdyn, vtu.
const std::vector<std::string> &export_formats();
/// The same as "mbdyn, vtu", for messages.
std::string export_format_list();

/// Writes @p body in @p format into @p directory (created if missing); returns the files
/// written. Throws InputError naming the entry @p entry for an unknown format, a folder that
/// cannot be written, or a body the format cannot hold.
std::vector<std::string> export_reduced_body(const reduction::ReducedBody &body, const std::string &format,
                                             const std::string &directory, const std::string &stem,
                                             const std::string &entry = "--format");
} // namespace flextrack::io
