// The reduced body file: HDF5, layout in doc/reduced_body_file.md. Written atomically (to a
// temporary name in the same folder, then renamed), so a failed or interrupted run never leaves
// a half-written file under the final name. Reading checks the format tag, the version and
// every dataset's shape, then the physical plausibility of the body (reduction/plausibility.h)
// and the content checksum written with the file, and throws InputError naming the file and
// the offending object or property.
#pragma once

#include <reduction/reduced_body.h>

#include <string>

namespace flextrack::io
{
/// Format tag stored in the root attribute "format".
inline const std::string reduced_body_format = "FlexTrack reduced body";
/// 2: arms carry "geometry_parameters" (their exact curve and section frame). 3: the root
/// attribute "content_checksum". 4: arms carry "section_outline" and the attribute
/// "track_stations", the drawing its point masses (for the animation's tubes and cubes). Files of other versions are refused ("reduce the body
/// again"), so a cached body is reduced again and gains what is new.
inline constexpr long long reduced_body_format_version = 4;

void write_reduced_body(const reduction::ReducedBody &body, const std::string &file);
reduction::ReducedBody read_reduced_body(const std::string &file);
} // namespace flextrack::io
