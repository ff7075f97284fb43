// Entries set on the command line: `--set ENTRY=VALUE` (repeatable, every command that reads a
// scene). ENTRY is the path print-parameters shows, subsections and entry joined by '/', e.g.
// "Multibody/End time" or "Joint slide/Driver". "Body NAME:PATH" sets PATH in the body scene of
// the flexible body NAME of a multibody scene (e.g. "Body arm1:Reduction/Number of normal modes").
//
// An override is applied after its scene file has been parsed, through the same ParameterHandler
// (so it is checked exactly like the file's own entries: declared, and its value matching the
// entry's pattern), and so it reaches parameters_used.prm, summary.json's parameters and the
// reduced-body cache's input hash like an entry of the file. A value may not hold a line break,
// '#' or a trailing '\' (the .prm syntax gives them a meaning of their own).
#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace flextrack::io
{
struct ParameterOverride
{
  std::string scope; ///< "" for the scene file itself, "Body NAME" for that body's body scene
  std::string path;  ///< "Subsection/.../Entry"
  std::string value;
  std::string text() const { return (scope.empty() ? "" : scope + ":") + path + "=" + value; }
};

/// Reads the text of one --set option; InputError (entry "--set") if it is malformed.
ParameterOverride parse_override(const std::string &text);

/// Sets the overrides of @p scope in @p prm (parsed already). With @p skip_undefined (a lenient
/// first pass) an entry @p prm does not declare is left for the strict pass; otherwise it is an
/// InputError naming the override, the subsection and the nearest declared names.
void apply_overrides(dealii::ParameterHandler &prm, const std::vector<ParameterOverride> &overrides,
                     const std::string &scope, bool skip_undefined);

/// deal.II's "The entry value V for the entry named E does not match the given pattern: [P]" as
/// "entry 'E' is 'V'; allowed: a, b, c" for a selection, "entry 'E' is 'V', which is not P" for
/// another pattern; empty if @p message is not such a mismatch (issue 25, item 6).
std::string explained_pattern_mismatch(const std::string &message);

/// Sets every input-file entry of @p prm (declared with Patterns::FileName: a body scene, a mesh,
/// a spline's points) that holds a relative path to the absolute path it names from
/// @p directory (the scene file's folder), so that parameters_used.prm runs from any folder.
void make_file_entries_absolute(dealii::ParameterHandler &prm, const std::string &directory);

/// The overrides of @p scope, as "PATH=VALUE" texts (for summary.json).
std::vector<std::string> override_texts(const std::vector<ParameterOverride> &overrides);

/// The declared names (entries and subsections) of subsection @p path ('/'-joined, "" for the
/// top level) of @p prm closest to @p name by edit distance (at most 3 edits, or the first
/// letters equal), best first, as the end of a message: "; nearest declared: 'a', 'b' (flextrack
/// print-parameters lists every entry)".
std::string nearest_declared_hint(const dealii::ParameterHandler &prm, const std::string &path, const std::string &name);
} // namespace flextrack::io
