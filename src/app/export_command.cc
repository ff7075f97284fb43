// flextrack export --format FORMAT BODY.h5 [-o DIR] [--mbdyn-clamp auto|yes|no]: the reduced body
// for other tools (io/body_export.h). Default folder: the one that holds BODY.h5. --mbdyn-clamp
// chooses whether the MBDyn .elm clamps the modal node (io::MbdynClamp; 'no' for a body that the
// including model hangs on a joint).
#include <app/commands.h>
#include <base/input_error.h>
#include <io/body_export.h>
#include <io/mbdyn_export.h>
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
  // Checked before the body is read: a wrong option is reported as such whatever the file.
  const bool clamp_given = !options.mbdyn_clamp.empty();
  const auto clamp = clamp_given ? io::mbdyn_clamp_from_name(options.mbdyn_clamp, "--mbdyn-clamp") : io::MbdynClamp::automatic;
  if (clamp_given && format.name != "mbdyn")
    throw InputError("--mbdyn-clamp", "applies to '--format mbdyn' only, not to '" + format.name + "'");
  const auto body = io::read_reduced_body(options.file);
  std::string dir = options.output_directory;
  if (dir.empty()) dir = fs::path(options.file).parent_path().string();
  if (dir.empty()) dir = ".";
  io::OutputFolder out(dir);
  const std::string stem = fs::path(options.file).stem().string();
  if (clamp_given)
    for (const auto &[name, text] : io::mbdyn_export_files(body, stem, clamp)) out.add_text(name, text);
  else
    io::export_reduced_body(body, format, out, stem);
  const auto files = out.commit();
  std::cout << "flextrack export: " << options.file << " (" << body.n_modes() << " modes, " << body.interfaces.size()
            << " interfaces) as " << options.format << (clamp_given ? ", modal node clamp: " + options.mbdyn_clamp : "")
            << ":\n";
  for (const auto &f : files) std::cout << "  " << f << "\n";
  return 0;
}
} // namespace flextrack::app
