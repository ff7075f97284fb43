#include <base/input_error.h>
#include <base/names.h>
#include <io/body_export.h>
#include <io/mbdyn_export.h>
#include <io/vtu_export.h>

namespace flextrack::io
{
namespace
{
std::vector<std::pair<std::string, std::string>> mbdyn_files(const reduction::ReducedBody &body, const std::string &stem)
{
  return {{stem + ".fem", mbdyn_fem_text(body)}, {stem + ".elm", mbdyn_elm_text(body, stem + ".fem")}};
}

std::vector<std::pair<std::string, std::string>> vtu_files(const reduction::ReducedBody &body, const std::string &stem)
{
  return {{stem + "_modes.vtu", mode_shapes_vtu_text(body)}};
}
} // namespace

const std::vector<ExportFormat> &export_formats()
{
  // The central table: a new format is one writer plus one row here.
  static const std::vector<ExportFormat> formats{
    {"mbdyn", "MBDyn modal joint: STEM.fem (modal element data) + STEM.elm (joint statement)", mbdyn_files},
    {"vtu", "mode shapes on the body's surface, STEM_modes.vtu (ParaView, meshio)", vtu_files}};
  return formats;
}

std::string export_format_list()
{
  std::string list;
  for (const auto &f : export_formats()) list += (list.empty() ? "" : ", ") + f.name;
  return list;
}

const ExportFormat &find_export_format(const std::string &name, const std::string &entry)
{
  for (const auto &f : export_formats())
    if (f.name == name) return f;
  throw InputError(entry, "unknown export format '" + base::printable_excerpt(name) + "'; allowed: " +
                            export_format_list());
}

std::vector<std::string> export_reduced_body(const reduction::ReducedBody &body, const ExportFormat &format,
                                             OutputFolder &folder, const std::string &stem)
{
  std::vector<std::string> names;
  for (const auto &[name, text] : format.files(body, stem))
    {
      folder.add_text(name, text);
      names.push_back(name);
    }
  return names;
}
} // namespace flextrack::io
