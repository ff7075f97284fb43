// A reduction scene: one flexible body (solid part, arms, ties, interfaces, point masses), its
// reduction settings and the output settings, read from a parameter file with "Model = body".
// Arms are named in "Body/Arms" and each has its own "subsection Arm NAME": the two-pass pattern
// of io/scene_file.h.
#pragma once

#include <fem/body.h>
#include <io/arm_scene.h>
#include <io/scene_file.h>
#include <reduction/component_modes.h>

#include <deal.II/base/parameter_handler.h>

#include <cstdint>
#include <memory>
#include <string>

namespace flextrack::io
{
struct BodyScene
{
  std::string file;
  fem::Body body;
  reduction::ReductionSettings reduction;
  OutputSettings output;
  /// 64-bit FNV-1a hash (hex) of every input that affects the reduced body: all parameters
  /// except "Output", and the contents of every file a parameter names (meshes, point files).
  std::string input_hash;
  /// The parameters as read (for parameters_used.prm and summary.json).
  std::shared_ptr<dealii::ParameterHandler> parameters;
};

/// Declares everything a body scene may contain, with "subsection Arm NAME" for each name.
void declare_body_scene(dealii::ParameterHandler &prm, const std::vector<std::string> &arm_names);

/// The body scene of @p scene (which must have "Model = body"). Throws InputError.
BodyScene read_body_scene(const SceneFile &scene);
/// Pass 2 of a body scene alone: declares every entry @p file may hold (the body, reduction,
/// output, static settings and load cases) in @p prm and parses the file strictly; InputError for
/// an undeclared entry or a value its pattern refuses. Builds nothing (no curve, no mesh).
void parse_body_scene_entries(const SceneFile &file, dealii::ParameterHandler &prm);
BodyScene read_body_scene(const std::string &file);
/// Same, from parameter text (tests); @p directory resolves relative file names.
BodyScene read_body_scene_from_string(const std::string &text, const std::string &directory = ".");

/// 64-bit FNV-1a hash of @p bytes, continuing from @p hash.
std::uint64_t fnv1a(const std::string &bytes, std::uint64_t hash = 14695981039346656037ull);
} // namespace flextrack::io
