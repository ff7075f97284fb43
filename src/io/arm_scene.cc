#include <io/arm_scene.h>
#include <io/body_export.h>
#include <base/input_error.h>
#include <base/parse_error.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace flextrack::io
{
using dealii::ParameterHandler;

void OutputSettings::declare_parameters(ParameterHandler &prm)
{
  prm.enter_subsection("Output");
  prm.declare_entry("Directory", "", dealii::Patterns::Anything(),
                    "Folder for the results; empty means output/<parameter file name without extension>. "
                    "The command-line option -o overrides it.");
  prm.declare_entry("Mode shapes", "true", dealii::Patterns::Bool(),
                    "Write the mass-normalised mode shapes as VTU files with a PVD index (ParaView).");
  prm.declare_entry("Subdivisions", "4", dealii::Patterns::Integer(1, 64),
                    "Subdivisions of each element in the VTU output, so curved elements look curved [-].");
  prm.declare_entry("Export formats", "", dealii::Patterns::Anything(),
                    "'flextrack reduce' only: also export the reduced body, formats separated by commas: "
                    "'mbdyn' (modal element data .fem + joint statement .elm), 'vtu' (mode shapes for ParaView).");
  prm.leave_subsection();
}

OutputSettings OutputSettings::parse_parameters(ParameterHandler &prm)
{
  OutputSettings s;
  prm.enter_subsection("Output");
  s.directory = prm.get("Directory");
  s.mode_shapes = prm.get_bool("Mode shapes");
  s.subdivisions = prm.get_integer("Subdivisions");
  std::string formats = prm.get("Export formats");
  for (auto &c : formats)
    if (c == ',') c = ' ';
  std::istringstream list(formats);
  for (std::string f; list >> f;)
    {
      const auto &known = io::export_formats();
      if (std::find(known.begin(), known.end(), f) == known.end())
        throw InputError("Output/Export formats", "unknown export format '" + f + "'; allowed: " + export_format_list());
      s.export_formats.push_back(f);
    }
  prm.leave_subsection();
  return s;
}

void declare_arm_scene(ParameterHandler &prm)
{
  prm.declare_entry("Model", "arm", dealii::Patterns::Selection("arm|solid"),
                    "The structure of the scene: 'arm' (a curved beam, subsection Arm) or 'solid' (a 3D body "
                    "meshed with hexahedra, subsection Solid).");
  fem::Arm::declare_parameters(prm);
  fem::Solid::declare_parameters(prm);
  reduction::ModalSettings::declare_parameters(prm);
  OutputSettings::declare_parameters(prm);
}

namespace
{
ArmScene build_scene(ParameterHandler &prm, const std::string &file, const std::string &directory)
{
  try
    {
      ArmScene scene;
      scene.file = file;
      scene.is_solid = prm.get("Model") == "solid";
      if (scene.is_solid)
        scene.solid = fem::Solid::parse_parameters(prm, directory);
      else
        scene.arm = fem::Arm::parse_parameters(prm, directory);
      scene.modal = reduction::ModalSettings::parse_parameters(prm);
      scene.output = OutputSettings::parse_parameters(prm);
      return scene;
    }
  catch (const InputError &e)
    {
      throw e.in_file(file);
    }
}

} // namespace

ArmScene read_arm_scene(const std::string &file, ParameterHandler &prm)
{
  if (!std::filesystem::is_regular_file(file) || !std::ifstream(file))
    throw InputError("", "cannot open the parameter file (missing or unreadable); give an existing .prm or .json file", file);
  try
    {
      prm.parse_input(file, "", false, true);
    }
  catch (const dealii::ExceptionBase &e)
    {
      throw InputError("", base::parse_error_text(e), file);
    }
  const auto parent = std::filesystem::path(file).parent_path().string();
  return build_scene(prm, file, parent.empty() ? "." : parent);
}

ArmScene read_arm_scene_from_string(const std::string &text, ParameterHandler &prm, const std::string &directory)
{
  try
    {
      prm.parse_input_from_string(text, "", false);
    }
  catch (const dealii::ExceptionBase &e)
    {
      throw InputError("", base::parse_error_text(e), "<string>");
    }
  return build_scene(prm, "<string>", directory);
}
} // namespace flextrack::io
