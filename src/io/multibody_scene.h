// A multibody scene ("set Model = multibody"): bodies, joints, forces and probes, each named in
// a list of `subsection Multibody` and described in its own `subsection KIND NAME` (the
// two-pass pattern of io/scene_file.h). Each subsection's entries are declared by the class that
// reads them (multibody::FloatingBody, the joint and force tables, multibody::Probe); this
// reader adds what belongs to io: where a flexible body comes from (a body scene, reduced on
// demand through the cache of io/reduced_body_cache.h, or a reduced body .h5 file).
//
// Every name a joint, force or probe refers to is checked against the body list before any body
// is built, so a misspelt name is reported (file, entry, allowed names) before any reduction
// runs or anything is written. The format is documented in doc/multibody.md.
#pragma once

#include <io/scene_file.h>
#include <multibody/probe.h>
#include <multibody/simulation_settings.h>
#include <multibody/system.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace flextrack::io
{
struct MultibodyScene
{
  std::string file;
  multibody::SceneNames names;
  multibody::SimulationSettings settings;
  std::unique_ptr<multibody::System> system; ///< finalised; initial conditions not yet made consistent
  std::vector<std::unique_ptr<multibody::Probe>> probes;
  /// One line per body: "crank: rigid, 0.5 kg", "boom: flexible, 26 modes (cached ...)".
  std::vector<std::string> body_descriptions;
  /// What the log should say of the scene as written (joint notes: a slider held off its track).
  std::vector<std::string> notes;
  std::string output_directory; ///< Output/Directory (empty: the default rule of OutputFolder)
  double animation_interval = 0; ///< Output/Animation interval [s]; 0: no animation
  bool plots = true;             ///< Output/Plots: run.png
  double max_results_gib = 2;     ///< Output/Maximum results size [GiB]
  /// The parameters as read (parameters_used.prm, summary.json).
  std::shared_ptr<dealii::ParameterHandler> parameters;
};

/// Declares everything a multibody scene with these names may contain.
void declare_multibody_scene(dealii::ParameterHandler &prm, const multibody::SceneNames &names);

/// Reads and builds the scene of @p file ("Model = multibody"). Reductions of flexible bodies are
/// logged to @p log and timed in @p timer; @p before_reduction is called once before the first
/// reduction that the cache cannot serve (the FE stage needs MPI started). @p every_body_rigid
/// builds every flexible body rigid whatever the scene says (as 'Multibody/Flexible bodies rigid =
/// true'): the rigid reference run of 'Multibody/Rigid reference'. InputError naming the file and
/// entry for bad input.
MultibodyScene read_multibody_scene(const SceneFile &file, std::ostream &log, dealii::TimerOutput &timer,
                                    const std::function<void()> &before_reduction = {}, bool every_body_rigid = false);
} // namespace flextrack::io
