#include <io/body_export.h>
#include <base/input_error.h>
#include <io/mbdyn_export.h>
#include <io/vtu_export.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <utility>

namespace flextrack::io
{
namespace fs = std::filesystem;

const std::vector<std::string> &export_formats()
{
  static const std::vector<std::string> formats{"mbdyn", "vtu"};
  return formats;
}

std::string export_format_list()
{
  std::string list;
  for (const auto &f : export_formats()) list += (list.empty() ? "" : ", ") + f;
  return list;
}

std::vector<std::string> export_reduced_body(const reduction::ReducedBody &body, const std::string &format,
                                             const std::string &directory, const std::string &stem,
                                             const std::string &entry)
{
  // Everything is produced in memory first: a body the format cannot hold writes nothing.
  std::vector<std::pair<std::string, std::string>> files; // name, text
  if (format == "mbdyn")
    {
      files.emplace_back(stem + ".fem", mbdyn_fem_text(body));
      files.emplace_back(stem + ".elm", mbdyn_elm_text(body, stem + ".fem"));
    }
  else if (format == "vtu")
    files.emplace_back(stem + "_modes.vtu", mode_shapes_vtu_text(body));
  else
    throw InputError(entry, "unknown export format '" + format + "'; allowed: " + export_format_list());

  std::error_code ec;
  fs::create_directories(directory, ec);
  if (ec || !fs::is_directory(directory))
    throw InputError("-o / Output/Directory", "cannot create the output folder '" + directory + "'" +
                                                (ec ? ": " + ec.message() : ""));
  std::vector<std::string> temporary, written;
  auto clean_up = [&] {
    for (const auto &t : temporary) fs::remove(t, ec);
  };
  for (const auto &[name, text] : files)
    {
      const std::string path = (fs::path(directory) / name).string();
      const std::string tmp = path + ".writing-" + std::to_string(getpid());
      temporary.push_back(tmp);
      std::ofstream out(tmp, std::ios::binary);
      out << text;
      out.close();
      if (!out)
        {
          clean_up();
          throw InputError("-o / Output/Directory", "cannot write '" + path + "' (is the folder writable?)");
        }
      written.push_back(path);
    }
  for (std::size_t i = 0; i < written.size(); ++i) fs::rename(temporary[i], written[i]);
  return written;
}
} // namespace flextrack::io
