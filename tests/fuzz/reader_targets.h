// The readers that take hostile input, each called the way the flextrack command line calls it
// (src/app/*.cc), for the fuzz driver fuzz_readers.cc:
//   scene  SceneFile::from_text, then the reader of the scene's Model: read_arm_scene ('modes',
//          'static' on arm and solid scenes; a solid reads its mesh file), read_body_scene
//          ('reduce'), read_multibody_scene ('run', 'linearize'; a flexible body whose reduced
//          body is not cached would be reduced: the run stops there, as skipped);
//   inp    fem::read_mesh_file on an Abaqus/CalculiX .inp file (Solid/Mesh file);
//   msh    fem::read_mesh_file on a Gmsh .msh file;
//   body   io::read_reduced_body ('inspect', 'export', a multibody scene's Reduced body file).
#pragma once

#include <string>
#include <vector>

namespace flextrack::fuzz
{
/// Thrown instead of reducing a flexible body (expensive, and it writes a cache): not an outcome
/// of the reader, so such an input counts as skipped.
struct NeedsReduction
{};

struct ReaderTarget
{
  std::string name;
  /// File name endings of its inputs (seeds and mutants keep their seed's ending).
  std::vector<std::string> extensions;
  bool hdf5;
  /// Reads @p file; relative names in a scene are taken from @p directory (the seed's folder).
  void (*read)(const std::string &file, const std::string &directory);
};

const std::vector<ReaderTarget> &reader_targets();
/// The target named @p name; nullptr if none.
const ReaderTarget *find_target(const std::string &name);
/// The target that reads files ending in the extension of @p file; nullptr if none.
const ReaderTarget *target_for_file(const std::string &file);
} // namespace flextrack::fuzz
