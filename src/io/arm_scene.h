// A modal-analysis scene: one arm, the eigen solver settings and the output settings, read
// from a deal.II parameter file (.prm, or .json).
#pragma once

#include <fem/arm.h>
#include <fem/load_case.h>
#include <fem/solid.h>
#include <io/scene_file.h>
#include <reduction/modal_solver.h>

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace flextrack::io
{
struct OutputSettings
{
  std::string directory;         ///< empty: output/<parameter file stem>
  bool mode_shapes = true;       ///< write VTU/PVD mode shapes
  unsigned int subdivisions = 4; ///< patch subdivisions per cell in the VTU files
  std::vector<std::string> export_formats; ///< reduce: also export the body (mbdyn, vtu)

  static void declare_parameters(dealii::ParameterHandler &prm);
  static OutputSettings parse_parameters(dealii::ParameterHandler &prm);
};

/// A modal-analysis scene: one structure, either a curved arm or a solid body.
struct ArmScene
{
  std::string file;
  bool is_solid = false; ///< "set Model = solid"
  fem::Arm arm;
  fem::Solid solid;
  reduction::ModalSettings modal;
  OutputSettings output;
  fem::StaticSettings statics;            ///< "subsection Static" ('flextrack static')
  std::vector<fem::LoadCase> load_cases; ///< one per name in Static/Load cases
};

void declare_arm_scene(dealii::ParameterHandler &prm);

/// Parse @p file (Model = arm or solid) into @p prm (declared by declare_arm_scene; the load case
/// subsections named in the file are declared here) and build the scene. Throws InputError naming the file and the entry.
ArmScene read_arm_scene(const SceneFile &file, dealii::ParameterHandler &prm);
ArmScene read_arm_scene(const std::string &file, dealii::ParameterHandler &prm);

/// Same, from parameter text (tests); @p directory resolves relative file names.
ArmScene read_arm_scene_from_string(const std::string &text, dealii::ParameterHandler &prm,
                                    const std::string &directory = ".");
} // namespace flextrack::io
