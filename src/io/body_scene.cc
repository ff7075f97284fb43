#include <io/body_scene.h>
#include <base/input_error.h>
#include <fem/load_case.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace flextrack::io
{
using dealii::ParameterHandler;
namespace fs = std::filesystem;

std::uint64_t fnv1a(const std::string &bytes, std::uint64_t hash)
{
  for (const unsigned char c : bytes)
    {
      hash ^= c;
      hash *= 1099511628211ull;
    }
  return hash;
}

namespace
{
/// Every parameter except the Output subsection, in deal.II's canonical short form, plus the
/// bytes of every file that a value names.
std::string hash_inputs(const ParameterHandler &prm, const std::string &directory)
{
  std::ostringstream printed;
  prm.print_parameters(printed, ParameterHandler::ShortPRM);
  std::istringstream lines(printed.str());
  std::uint64_t h = fnv1a(std::string("flextrack reduced body v1 ") + FLEXTRACK_VERSION);
  int skip_depth = 0, depth = 0;
  for (std::string line; std::getline(lines, line);)
    {
      const auto start = line.find_first_not_of(' ');
      const std::string t = start == std::string::npos ? "" : line.substr(start);
      if (t.rfind("subsection ", 0) == 0)
        {
          ++depth;
          // Output settings and load cases do not change the reduced body.
          if (skip_depth == 0 && depth == 1 &&
              (t == "subsection Output" || t == "subsection Static" || t.rfind("subsection Load case ", 0) == 0))
            skip_depth = depth;
        }
      else if (t == "end")
        {
          if (skip_depth == depth) skip_depth = 0;
          --depth;
          continue;
        }
      if (skip_depth) continue;
      h = fnv1a(t + "\n", h);
      if (const auto eq = t.find(" = "); t.rfind("set ", 0) == 0 && eq != std::string::npos)
        {
          const std::string value = t.substr(eq + 3);
          if (value.empty() || value.find_first_of("\n,;") != std::string::npos) continue;
          const fs::path p = fs::path(value).is_absolute() ? fs::path(value) : fs::path(directory) / value;
          std::error_code ec;
          if (fs::is_regular_file(p, ec))
            {
              std::ifstream in(p, std::ios::binary);
              std::ostringstream bytes;
              bytes << in.rdbuf();
              h = fnv1a(bytes.str(), h);
            }
        }
    }
  std::ostringstream hex;
  hex << std::hex << std::setw(16) << std::setfill('0') << h;
  return hex.str();
}

} // namespace

BodyScene read_body_scene(const SceneFile &file)
{
  try
    {
      if (file.model != "body")
        throw InputError("Model", "'" + file.model + "' scenes are analysed by 'flextrack modes'; "
                                  "'flextrack reduce' needs 'Model = body'");
      // Pass 2: everything, strictly.
      BodyScene scene;
      scene.file = file.name;
      scene.parameters = std::make_shared<ParameterHandler>();
      parse_body_scene_entries(file, *scene.parameters);
      auto &prm = *scene.parameters;
      scene.body = fem::Body::parse_parameters(prm, file.directory, file.has_subsection("Solid"));
      scene.reduction = reduction::ReductionSettings::parse_parameters(prm);
      scene.output = OutputSettings::parse_parameters(prm);
      scene.input_hash = hash_inputs(prm, file.directory);
      return scene;
    }
  catch (const InputError &e)
    {
      throw e.file().empty() ? e.in_file(file.name) : e;
    }
}

void parse_body_scene_entries(const SceneFile &file, ParameterHandler &prm)
{
  declare_body_scene(prm, fem::Body::parse_arm_list(*file.lists));
  // Load cases are read by 'flextrack static' (app/static_command.cc); declared here too so
  // that 'reduce' and 'run' accept a body scene that has them (they stay out of the hash).
  fem::StaticSettings::declare_parameters(prm);
  fem::LoadCase::declare_parameters(prm, fem::StaticSettings::parse_load_case_list(*file.lists));
  file.parse(prm, false);
}

void declare_body_scene(ParameterHandler &prm, const std::vector<std::string> &arm_names)
{
  declare_model_entry(prm);
  fem::Body::declare_parameters(prm, arm_names);
  reduction::ModalSettings::declare_parameters(prm);
  reduction::ReductionSettings::declare_parameters(prm);
  OutputSettings::declare_parameters(prm);
}

BodyScene read_body_scene(const std::string &file) { return read_body_scene(SceneFile::read(file)); }

BodyScene read_body_scene_from_string(const std::string &text, const std::string &directory)
{
  return read_body_scene(SceneFile::from_text(text, directory));
}
} // namespace flextrack::io
