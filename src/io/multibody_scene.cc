// Reading a multibody scene (multibody_scene.h).
#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>
#include <io/body_scene.h>
#include <io/multibody_scene.h>
#include <io/output_folder.h>
#include <io/reduced_body_cache.h>
#include <io/reduced_body_file.h>
#include <multibody/force.h>
#include <multibody/joint_table.h>

#include <deal.II/base/symmetric_tensor.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <sstream>
#include <tuple>

namespace flextrack::io
{
using dealii::ParameterHandler;
namespace Patterns = dealii::Patterns;
namespace fs = std::filesystem;
using namespace multibody;

namespace
{
void declare_body_source(ParameterHandler &prm)
{
  prm.declare_entry("Kind", "rigid", Patterns::Selection("rigid|flexible"),
                    "Kind of body [-]: 'rigid' (Mass, Centre of mass, Inertia) or 'flexible' (a reduced body "
                    "from 'Body scene' or 'Reduced body file').");
  prm.declare_entry("Body scene", "", Patterns::FileName(Patterns::FileName::input),
                    "Flexible body: a 'Model = body' scene file (relative to this scene's folder). It is reduced "
                    "on demand; the reduced body is kept where 'flextrack reduce' keeps it (the body scene's "
                    "Output/Directory, else output/<its name>/reduced_body.h5) and reused while its inputs "
                    "are unchanged [-].");
  prm.declare_entry("Reduced body file", "", Patterns::FileName(Patterns::FileName::input),
                    "Flexible body: a reduced body file (.h5, written by 'flextrack reduce'; relative to this "
                    "scene's folder) [-].");
}

void in_instance(ParameterHandler &prm, const std::string &kind, const std::string &name,
                 const std::function<void()> &what)
{
  prm.enter_subsection(kind + " " + name);
  what();
  prm.leave_subsection();
}

using base::joined;

/// Every body name an instance refers to exists (entry, allowed names); checked before anything
/// is built, so that no reduction runs for a scene with a typo.
void check_references(ParameterHandler &prm, const SceneNames &names)
{
  std::vector<std::string> allowed{ground_name};
  allowed.insert(allowed.end(), names.bodies.begin(), names.bodies.end());
  const auto check = [&](const std::string &instance, const std::string &entry, const std::string &value) {
    const std::string name = base::trim(value);
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw InputError(instance + "/" + entry,
                       "there is no body '" + base::printable_excerpt(name) + "'; allowed: " + joined(allowed));
  };
  for (const auto &j : names.joints)
    in_instance(prm, "Joint", j, [&] {
      check("Joint " + j, "Body 1", prm.get("Body 1"));
      check("Joint " + j, "Body 2", prm.get("Body 2"));
    });
  for (const auto &f : names.forces)
    in_instance(prm, "Force", f, [&] {
      check("Force " + f, "Body 1", prm.get("Body 1"));
      if (prm.get("Kind") != "applied load") check("Force " + f, "Body 2", prm.get("Body 2"));
    });
  for (const auto &p : names.probes)
    in_instance(prm, "Probe", p, [&] {
      check("Probe " + p, "Body", prm.get("Body"));
      if (base::trim(prm.get("Frame")) != "global") check("Probe " + p, "Frame", prm.get("Frame"));
    });
}

/// The largest magnitude a number of an entry may have: far beyond any machine (a position of
/// 1000 km, a speed of 1000 km/s), yet small enough that squares and products of such numbers
/// stay finite and the integrator's error weights meaningful. Rows: subsection kind, entry,
/// limit, unit. A larger number (1e300, say) is refused with the entry's name instead of
/// failing deep inside a factorisation or the integrator.
struct Limit
{
  const char *kind, *entry;
  double limit;
  const char *unit;
};
const Limit limits[] = {
  {"Multibody", "Gravity", 1e6, "m/s^2"},        {"Multibody", "Start time", 1e9, "s"},
  {"Multibody", "End time", 1e9, "s"},           {"Multibody", "Output interval", 1e9, "s"},
  {"Body", "Mass", 1e12, "kg"},                  {"Body", "Centre of mass", 1e6, "m"},
  {"Body", "Inertia", 1e15, "kg m^2"},           {"Body", "Position", 1e6, "m"},
  {"Body", "Rotation vector", 1e6, "rad"},       {"Body", "Euler parameters", 1e6, "-"},
  // 1e4 m/s is beyond any projectile a mechanism carries; 1e5 rad/s (955 000 rpm) beyond any
  // spindle or turbine. At 1e6 a 1 s pendulum took 566 502 steps and 41 s of CPU (issue 23).
  {"Body", "Velocity", 1e4, "m/s"},              {"Body", "Angular velocity", 1e5, "rad/s"},
  {"Body", "Modal coordinates", 1e6, "modal units"}, {"Body", "Modal velocities", 1e6, "modal units/s"},
  {"Joint", "Position", 1e6, "m"},               {"Joint", "Axis", 1e6, "-"},
  {"Joint", "Reference axis", 1e6, "-"},         {"Force", "Position 1", 1e6, "m"},
  {"Force", "Position 2", 1e6, "m"},             {"Force", "Axis", 1e6, "-"},
  {"Force", "Stiffness", 1e15, "N/m or N m/rad"}, {"Force", "Damping", 1e15, "N s/m or N m s/rad"},
  {"Force", "Free length", 1e6, "m"},            {"Force", "Free angle", 1e6, "rad"},
  {"Probe", "Position", 1e6, "m"},
};

/// Every number of the entries of @p limits within bounds (the current subsection is of @p kind).
void check_magnitudes(ParameterHandler &prm, const std::string &kind, const std::string &instance)
{
  for (const auto &l : limits)
    {
      if (kind != l.kind) continue;
      const std::string entry = instance + l.entry;
      for (const auto &word : base::words(prm.get(l.entry)))
        if (std::abs(base::parse_number(word, entry, std::string("a number [") + l.unit + "]")) > l.limit)
          {
            std::ostringstream bound;
            bound << "every number must lie within +-" << l.limit << " " << l.unit << ", not " << base::printable_excerpt(word);
            throw InputError(entry, bound.str());
          }
    }
}

void check_all_magnitudes(ParameterHandler &prm, const SceneNames &names)
{
  const std::pair<const char *, const std::vector<std::string> *> instances[] = {
    {"Body", &names.bodies}, {"Joint", &names.joints}, {"Force", &names.forces}, {"Probe", &names.probes}};
  for (const auto &[kind, list] : instances)
    for (const auto &name : *list)
      in_instance(prm, kind, name, [&] { check_magnitudes(prm, kind, std::string(kind) + " " + name + "/"); });
}

/// A rigid body's inertia tensor is positive definite and its principal moments satisfy the
/// triangle inequality J_i <= J_j + J_k (a real mass distribution has both).
void check_inertia(const RigidProperties &r, const std::string &entry)
{
  dealii::SymmetricTensor<2, 3> J;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = i; j < 3; ++j) J[i][j] = r.inertia_centre_of_mass[i][j];
  const auto e = dealii::eigenvalues(J); // descending
  const double scale = std::max(std::abs(e[0]), 1e-300);
  if (!(e[2] > 1e-12 * scale) || e[0] > (e[1] + e[2]) * (1 + 1e-12))
    throw InputError(entry, "is not the inertia of a body: the principal moments (" + std::to_string(e[0]) + ", " +
                              std::to_string(e[1]) + ", " + std::to_string(e[2]) +
                              " kg m^2) must be positive and none larger than the sum of the others");
}

/// @p read(), with an error about a whole file (a missing file, not a body scene) attributed to
/// @p entry of this scene; errors inside the other file keep naming that file and its entry.
template <typename Read>
auto naming_entry(const std::string &entry, const Read &read)
{
  try
    {
      return read();
    }
  catch (const InputError &e)
    {
      if (!e.entry().empty() && e.entry() != "Model") throw;
      throw InputError(entry, e.what());
    }
}

/// Where a flexible body comes from, and the reduced body.
class FlexibleBodySource
{
public:
  FlexibleBodySource(const SceneFile &scene, std::ostream &log, dealii::TimerOutput &timer,
                     const std::function<void()> &before_reduction)
    : scene(scene), log(log), timer(timer), before_reduction(before_reduction)
  {}

  /// The reduced body named in the current `subsection Body NAME`; @p description says whence.
  std::shared_ptr<const reduction::ReducedBody> obtain(ParameterHandler &prm, const std::string &name,
                                                       std::string &description)
  {
    const std::string prefix = "Body " + name + "/";
    const std::string body_scene = base::trim(prm.get("Body scene")), body_file = base::trim(prm.get("Reduced body file"));
    if (body_scene.empty() == body_file.empty())
      throw InputError(prefix + "Body scene", "a flexible body needs exactly one of 'Body scene' and 'Reduced body file'");
    const auto overrides = scene.overrides_of(name);
    if (!overrides.empty() && !body_file.empty())
      throw InputError("--set", "'Body " + name + ":" + overrides.front().path + "': body '" + name + "' is read from "
                                "a reduced body file, which has no entries to set; give it a 'Body scene' instead");
    // Several bodies of one reduced body (a chain of equal links) share it: read, checked and
    // reduced once (issue 24, item 6: each instance was read again, 0.16 s each).
    std::error_code error;
    const std::string path = relative(body_file.empty() ? body_scene : body_file);
    // The same body scene with other --set entries is another body.
    std::string key = (body_file.empty() ? "scene " : "file ") + fs::weakly_canonical(path, error).string();
    for (const auto &o : overrides) key += "\n" + o.text();
    if (const auto known = obtained.find(key); !error && known != obtained.end())
      {
        description = known->second.second + ", shared";
        return known->second.first;
      }
    std::shared_ptr<const reduction::ReducedBody> body = read_or_reduce(prefix, body_scene, body_file, overrides, description);
    if (!error) obtained.emplace(key, std::make_pair(body, description));
    return body;
  }

  /// The --set entries of body @p name's body scene.
  std::vector<ParameterOverride> scene_overrides(const std::string &name) const { return scene.overrides_of(name); }

private:
  std::shared_ptr<const reduction::ReducedBody> read_or_reduce(const std::string &prefix, const std::string &body_scene,
                                                               const std::string &body_file,
                                                               const std::vector<ParameterOverride> &overrides,
                                                               std::string &description)
  {
    if (!body_file.empty())
      {
        dealii::TimerOutput::Scope t(timer, "load reduced bodies");
        auto body = std::make_shared<reduction::ReducedBody>(
          naming_entry(prefix + "Reduced body file", [&] { return read_reduced_body(relative(body_file)); }));
        description = "reduced body file " + relative(body_file);
        return body;
      }
    const auto source =
      naming_entry(prefix + "Body scene", [&] { return read_body_scene(SceneFile::read(relative(body_scene), overrides)); });
    // A body scene with --set entries is another body, kept in a file of its own beside the
    // scene's (named by its input hash): a study of several bases (flextrack sweep) reduces each
    // once and keeps it, and never replaces the body of the scene as written.
    const std::string cache = OutputFolder::choose("", source.output.directory, source.file) +
                              (overrides.empty() ? "/reduced_body.h5" : "/reduced_body_set_" + source.input_hash + ".h5");
    log << "  body scene " << source.file << ":\n";
    // Prepared (MPI started) only for a reduction the cache cannot serve, which the cache knows
    // only after reading and checking its file in full: a damaged file with the right input hash
    // is reduced too (issue 23; the input hash alone had left MPI unstarted there).
    auto reduced = cached_or_reduced_body(source, cache, log, timer, [this] {
      if (before_reduction && !reduction_prepared) before_reduction();
      reduction_prepared = true;
    });
    description = "body scene " + source.file + (reduced.from_cache ? ", reduced body from the cache " : ", reduced to ") + cache;
    return std::make_shared<reduction::ReducedBody>(std::move(reduced.body));
  }

  std::string relative(const std::string &path) const
  {
    return fs::path(path).is_absolute() ? path : (fs::path(scene.directory) / path).string();
  }
  const SceneFile &scene;
  std::ostream &log;
  dealii::TimerOutput &timer;
  const std::function<void()> &before_reduction;
  bool reduction_prepared = false;
  /// Reduced bodies obtained so far, by "scene PATH" or "file PATH" (canonical), with whence.
  std::map<std::string, std::pair<std::shared_ptr<const reduction::ReducedBody>, std::string>> obtained;
};

std::unique_ptr<FloatingBody> make_body(ParameterHandler &prm, const std::string &name, const SimulationSettings &settings,
                                        FlexibleBodySource &flexible, std::string &description)
{
  const std::string prefix = "Body " + name + "/";
  const InitialState initial = FloatingBody::parse_initial_state_parameters(prm, prefix);
  std::ostringstream d;
  d << name << ": ";
  if (prm.get("Kind") == "rigid")
    {
      if (const auto overrides = flexible.scene_overrides(name); !overrides.empty())
        throw InputError("--set", "'Body " + name + ":" + overrides.front().path + "': body '" + name +
                                    "' is rigid: it has no body scene whose entries could be set");
      RigidProperties properties;
      try
        {
          properties = FloatingBody::parse_rigid_parameters(prm);
        }
      catch (const InputError &e)
        {
          throw InputError(prefix + e.entry(), e.message());
        }
      check_inertia(properties, prefix + "Inertia");
      d << "rigid, " << properties.mass << " kg";
      description = d.str();
      return std::make_unique<FloatingBody>(name, properties, initial);
    }
  FlexibleOptions options = FloatingBody::parse_flexible_parameters(prm);
  options.make_rigid = options.make_rigid || settings.flexible_as_rigid;
  std::string source;
  auto reduced = flexible.obtain(prm, name, source);
  auto body = std::make_unique<FloatingBody>(name, reduced, options, initial);
  d << (options.make_rigid ? "flexible made rigid" : "flexible") << ", " << body->n_modes() << " modes, "
    << reduced->invariants.mass << " kg (" << source << ")";
  // 'Geometric stiffening = true' (the default) needs the reduced body's geometric stiffness,
  // which a body scene computes only when asked: said here, not switched off without a word
  // (issue 25, item 4).
  if (options.geometric_stiffening && !options.make_rigid && body->n_modes() > 0 && reduced->geometric_stiffness.empty())
    d << "; no geometric stiffening: the reduced body holds no geometric stiffness (Reduction/Geometric "
         "stiffness = true where it is reduced adds it, for a body that turns fast)";
  description = d.str();
  return body;
}
} // namespace

void declare_multibody_scene(ParameterHandler &prm, const SceneNames &names)
{
  declare_model_entry(prm);
  SceneNames::declare_name_lists(prm);
  SimulationSettings::declare_parameters(prm);
  for (const auto &b : names.bodies)
    in_instance(prm, "Body", b, [&] {
      declare_body_source(prm);
      FloatingBody::declare_rigid_parameters(prm);
      FloatingBody::declare_flexible_parameters(prm);
      FloatingBody::declare_initial_state_parameters(prm);
    });
  for (const auto &j : names.joints) in_instance(prm, "Joint", j, [&] { declare_joint_parameters(prm); });
  for (const auto &f : names.forces) in_instance(prm, "Force", f, [&] { declare_force_parameters(prm); });
  for (const auto &p : names.probes) in_instance(prm, "Probe", p, [&] { Probe::declare_parameters(prm); });
  prm.enter_subsection("Output");
  prm.declare_entry("Directory", "", Patterns::Anything(),
                    "Folder of the results (-o overrides it); empty: output/<scene file name> [-].");
  prm.declare_entry("Animation interval", "0", Patterns::Double(0),
                    "Time between the frames of the VTU/PVD animation (animation.pvd, one animation_NNNNN.vtu "
                    "per frame, taken at the output rows) [s]; 0: no animation.");
  prm.declare_entry("Plots", "true", Patterns::Bool(),
                    "Draw run.png after a run with gnuplot (run.gp, from probes.csv and monitors.csv): the probes' "
                    "coordinates [m], the energies [J], the energy balance error [-] and the constraint residuals "
                    "[m, m/s] against time [s]; false: none (a study's cases, where sweep.png is the picture).");
  prm.declare_entry("Maximum results size", "2", Patterns::Double(0),
                    "Largest estimated size of a run's results on disk (results.h5 and the CSV files, all written "
                    "as the run goes) [GiB], 0.001 to 1000; a scene whose output rows need more is refused before the "
                    "run. Raise it for a long run on purpose, or choose a longer Multibody/Output interval.");
  prm.leave_subsection();
}

MultibodyScene read_multibody_scene(const SceneFile &file, std::ostream &log, dealii::TimerOutput &timer,
                                    const std::function<void()> &before_reduction, const bool every_body_rigid)
{
  try
    {
      if (file.model != "multibody")
        throw InputError("Model", "is '" + file.model + "'; 'flextrack run' and 'flextrack linearize' need 'Model = "
                                  "multibody' (see doc/multibody.md)");
      MultibodyScene scene;
      scene.file = file.name;
      scene.names = SceneNames::parse_name_lists(*file.lists);
      for (const auto &o : file.overrides)
        if (!o.scope.empty() && std::find(scene.names.bodies.begin(), scene.names.bodies.end(), o.scope.substr(5)) ==
                                  scene.names.bodies.end())
          throw InputError("--set", "'" + base::printable_excerpt(o.text(), 200) + "': the scene has no body '" +
                                      base::printable_excerpt(o.scope.substr(5), 80) + "'; its bodies: " +
                                      base::joined(scene.names.bodies));
      // Pass 2: everything, strictly.
      scene.parameters = std::make_shared<ParameterHandler>();
      auto &prm = *scene.parameters;
      declare_multibody_scene(prm, scene.names);
      std::vector<std::string> subsections;
      for (const auto &b : scene.names.bodies) subsections.push_back("Body " + b);
      for (const auto &j : scene.names.joints) subsections.push_back("Joint " + j);
      for (const auto &f : scene.names.forces) subsections.push_back("Force " + f);
      for (const auto &p : scene.names.probes) subsections.push_back("Probe " + p);
      file.with_mangled_json_keys(subsections).parse(prm, false);
      prm.enter_subsection("Multibody");
      check_magnitudes(prm, "Multibody", "Multibody/");
      prm.leave_subsection();
      check_all_magnitudes(prm, scene.names);
      scene.settings = SimulationSettings::parse_parameters(prm);
      scene.settings.flexible_as_rigid = scene.settings.flexible_as_rigid || every_body_rigid;
      prm.enter_subsection("Output");
      scene.output_directory = base::trim(prm.get("Directory"));
      scene.animation_interval = prm.get_double("Animation interval");
      scene.plots = prm.get_bool("Plots");
      scene.max_results_gib = prm.get_double("Maximum results size");
      if (!(scene.max_results_gib >= 1e-3 && scene.max_results_gib <= 1e3))
        throw InputError("Output/Maximum results size", "must be from 0.001 to 1000 GiB");
      prm.leave_subsection();
      if (scene.animation_interval > 0 &&
          (scene.settings.end_time - scene.settings.start_time) / scene.animation_interval > 1e5)
        throw InputError("Output/Animation interval", "asks for more than 1e5 frames; choose a longer interval");
      check_references(prm, scene.names);
      // A listed instance without its subsection got every default: a body became 1 kg at the
      // origin, a joint a revolute of that body to the ground.
      for (const auto &[list, kind, names] :
           {std::make_tuple("Bodies", "Body", &scene.names.bodies), std::make_tuple("Joints", "Joint", &scene.names.joints),
            std::make_tuple("Forces", "Force", &scene.names.forces), std::make_tuple("Probes", "Probe", &scene.names.probes)})
        for (const auto &name : *names)
          if (!file.has_subsection(std::string(kind) + " " + name))
            throw InputError(std::string("Multibody/") + list, std::string(kind) + " '" + name + "' is listed but has no "
                               "'subsection " + kind + " " + name + "': describe it there, or take it out of the list");

      scene.system = std::make_unique<System>(scene.settings.gravity);
      auto &system = *scene.system;
      FlexibleBodySource flexible(file, log, timer, before_reduction);
      for (const auto &b : scene.names.bodies)
        in_instance(prm, "Body", b, [&] {
          std::string description;
          system.add_body(make_body(prm, b, scene.settings, flexible, description));
          scene.body_descriptions.push_back(description);
        });
      const auto lookup = system.body_lookup();
      const geometry::TimeWindow window{scene.settings.start_time, scene.settings.end_time}; // laws checked over it
      for (const auto &j : scene.names.joints)
        in_instance(prm, "Joint", j, [&] {
          auto joint = create_joint(j, prm, lookup, window);
          if (!joint->note().empty()) scene.notes.push_back("joint " + j + ": " + joint->note());
          system.add_joint(std::move(joint));
        });
      for (const auto &f : scene.names.forces)
        in_instance(prm, "Force", f, [&] { system.add_force(create_force(f, prm, lookup, window)); });
      for (const auto &p : scene.names.probes)
        in_instance(prm, "Probe", p, [&] { scene.probes.push_back(Probe::create(p, prm, lookup)); });
      system.finalize();
      return scene;
    }
  catch (const InputError &e)
    {
      throw e.file().empty() || e.file() == "<string>" ? e.in_file(file.name) : e;
    }
}
} // namespace flextrack::io
