#include "reader_targets.h"

#include <fem/solid_mesh.h>
#include <io/arm_scene.h>
#include <io/body_scene.h>
#include <io/multibody_scene.h>
#include <io/reduced_body_file.h>
#include <io/scene_file.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace flextrack::fuzz
{
namespace
{
std::string extension(const std::string &file) { return std::filesystem::path(file).extension().string(); }

void read_scene(const std::string &file, const std::string &directory)
{
  // SceneFile::read would take relative names from the mutant's folder; the seed's keeps the
  // meshes, includes and body files of the seed reachable, so the readers behind them run too.
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  io::SceneFile scene = io::SceneFile::from_text(text.str(), directory, extension(file) == ".json");
  scene.name = file;
  if (scene.model == "multibody")
    {
      std::ostringstream log;
      dealii::TimerOutput timer(log, dealii::TimerOutput::never, dealii::TimerOutput::wall_times);
      io::read_multibody_scene(scene, log, timer, [] { throw NeedsReduction(); });
    }
  else if (scene.model == "body")
    io::read_body_scene(scene);
  else
    {
      dealii::ParameterHandler prm;
      io::declare_arm_scene(prm);
      io::read_arm_scene(scene, prm);
    }
}

void read_mesh(const std::string &file, const std::string &) { fem::read_mesh_file(file, "Solid/Mesh file"); }

void read_body(const std::string &file, const std::string &) { io::read_reduced_body(file); }
} // namespace

const std::vector<ReaderTarget> &reader_targets()
{
  static const std::vector<ReaderTarget> targets{{"scene", {".prm", ".json"}, false, read_scene},
                                                 {"inp", {".inp"}, false, read_mesh},
                                                 {"msh", {".msh"}, false, read_mesh},
                                                 {"body", {".h5"}, true, read_body}};
  return targets;
}

const ReaderTarget *find_target(const std::string &name)
{
  for (const auto &t : reader_targets())
    if (t.name == name) return &t;
  return nullptr;
}

const ReaderTarget *target_for_file(const std::string &file)
{
  const std::string e = extension(file);
  for (const auto &t : reader_targets())
    if (std::find(t.extensions.begin(), t.extensions.end(), e) != t.extensions.end()) return &t;
  return nullptr;
}
} // namespace flextrack::fuzz
