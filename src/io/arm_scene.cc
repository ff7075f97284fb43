#include <base/text.h>
#include <io/arm_scene.h>
#include <io/body_export.h>
#include <base/input_error.h>

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
  for (const auto &f : base::words(prm.get("Export formats")))
    s.export_formats.push_back(find_export_format(f, "Output/Export formats").name);
  prm.leave_subsection();
  return s;
}

void declare_arm_scene(ParameterHandler &prm)
{
  declare_model_entry(prm);
  fem::Arm::declare_parameters(prm);
  fem::Solid::declare_parameters(prm);
  reduction::ModalSettings::declare_parameters(prm);
  OutputSettings::declare_parameters(prm);
  fem::StaticSettings::declare_parameters(prm);
}

ArmScene read_arm_scene(const SceneFile &file, ParameterHandler &prm)
{
  try
    {
      if (file.model == "body")
        throw InputError("Model", "a 'body' scene is reduced by 'flextrack reduce', not analysed as one arm or solid");
      const auto load_case_names = fem::StaticSettings::parse_load_case_list(*file.lists);
      fem::LoadCase::declare_parameters(prm, load_case_names);
      file.parse(prm, false);
      ArmScene scene;
      scene.file = file.name;
      scene.is_solid = file.model == "solid";
      if (scene.is_solid)
        scene.solid = fem::Solid::parse_parameters(prm, file.directory);
      else
        scene.arm = fem::Arm::parse_parameters(prm, file.directory);
      scene.modal = reduction::ModalSettings::parse_parameters(prm);
      scene.output = OutputSettings::parse_parameters(prm);
      const fem::Arm *arm = scene.is_solid ? nullptr : &scene.arm;
      const fem::Solid *solid = scene.is_solid ? &scene.solid : nullptr;
      scene.statics = fem::StaticSettings::parse_parameters(prm, arm, solid);
      for (const auto &name : scene.statics.load_cases)
        scene.load_cases.push_back(fem::LoadCase::parse_parameters(prm, name, arm, solid));
      return scene;
    }
  catch (const InputError &e)
    {
      throw e.file().empty() ? e.in_file(file.name) : e;
    }
}

ArmScene read_arm_scene(const std::string &file, ParameterHandler &prm)
{
  return read_arm_scene(SceneFile::read(file), prm);
}

ArmScene read_arm_scene_from_string(const std::string &text, ParameterHandler &prm, const std::string &directory)
{
  return read_arm_scene(SceneFile::from_text(text, directory), prm);
}
} // namespace flextrack::io
