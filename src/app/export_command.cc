// flextrack export --format FORMAT BODY.h5 [-o DIR]: the reduced body for other tools
// (io/body_export.h). Default folder: the one that holds BODY.h5.
#include <app/commands.h>
#include <io/body_export.h>
#include <io/output_folder.h>
#include <io/reduced_body_file.h>

#include <filesystem>
#include <iostream>

namespace flextrack::app
{
namespace fs = std::filesystem;

int export_command(const Options &options)
{
  const auto &format = io::find_export_format(options.format, "--format");
  const auto body = io::read_reduced_body(options.file);
  std::string dir = options.output_directory;
  if (dir.empty()) dir = fs::path(options.file).parent_path().string();
  if (dir.empty()) dir = ".";
  io::OutputFolder out(dir);
  io::export_reduced_body(body, format, out, fs::path(options.file).stem().string());
  const auto files = out.commit();
  std::cout << "flextrack export: " << options.file << " (" << body.n_modes() << " modes, " << body.interfaces.size()
            << " interfaces) as " << options.format << ":\n";
  for (const auto &f : files) std::cout << "  " << f << "\n";
  return 0;
}
} // namespace flextrack::app
