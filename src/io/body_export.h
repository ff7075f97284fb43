// Exports of a reduced body for other tools, one row each in a central table (body_export.cc):
//   mbdyn: STEM.fem (modal element data) and STEM.elm (a modal joint statement to include)
//   vtu:   STEM_modes.vtu (mode shapes on the body's surface, Float64; ParaView, meshio)
// The files are produced in memory first (a body the format cannot hold writes nothing) and
// staged in an OutputFolder, which renames them when the run has succeeded.
#pragma once

#include <io/output_folder.h>
#include <reduction/reduced_body.h>

#include <string>
#include <utility>
#include <vector>

namespace flextrack::io
{
struct ExportFormat
{
  std::string name;        ///< as given to --format and Output/Export formats
  std::string description; ///< for --help and print-parameters
  /// (file name, text) pairs of @p body, files named after @p stem.
  std::vector<std::pair<std::string, std::string>> (*files)(const reduction::ReducedBody &body, const std::string &stem);
};

/// Every format, in the order of the table.
const std::vector<ExportFormat> &export_formats();
/// "mbdyn, vtu", for messages.
std::string export_format_list();
/// The format called @p name; InputError naming @p entry (and the allowed names) if none is.
const ExportFormat &find_export_format(const std::string &name, const std::string &entry);

/// Stages @p body in @p format in @p folder; returns the file names (without folder).
std::vector<std::string> export_reduced_body(const reduction::ReducedBody &body, const ExportFormat &format,
                                             OutputFolder &folder, const std::string &stem);
} // namespace flextrack::io
