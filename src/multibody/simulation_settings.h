// The top-level settings of a multibody scene (`subsection Multibody`): the names of its bodies,
// joints, forces and probes, gravity, the time span, the output rate and the integrator.
//
// The name lists are read in the first pass of the scene file (io/scene_file.h) so that the
// second pass can declare one `subsection Body NAME`, `Joint NAME`, `Force NAME`, `Probe NAME`
// per name. The ground is always there, under the name "ground"; it is not listed.
#pragma once

#include <multibody/body.h>
#include <multibody/time_integrator.h>

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace flextrack::multibody
{
/// The name of the fixed frame that every scene has.
inline const std::string ground_name = "ground";

struct SceneNames
{
  std::vector<std::string> bodies, joints, forces, probes;

  /// Declares Multibody/Bodies, Joints, Forces, Probes (pass 1 and pass 2 alike).
  static void declare_name_lists(dealii::ParameterHandler &prm);
  /// The lists; InputError naming the entry for a bad or repeated name, or a body named "ground".
  static SceneNames parse_name_lists(dealii::ParameterHandler &prm);
};

struct SimulationSettings
{
  Vector3 gravity;                 ///< [m/s^2], global
  double start_time = 0;           ///< [s]
  double end_time = 1;             ///< [s]
  double output_interval = 0.01;   ///< [s] between output rows
  bool flexible_as_rigid = false;  ///< every flexible body rigid (same m, s, J_O): deviation studies
  /// `flextrack run` also runs the scene with every body rigid and writes the probes' deviation
  /// from that nominal path (deviation.csv, deviation.png).
  bool rigid_reference = false;
  /// Start from the static equilibrium under gravity and the loads at the start time (entry
  /// `Initial state = static equilibrium`; multibody/static_equilibrium.h) instead of the
  /// positions and velocities as given (`as given`, the default).
  bool static_equilibrium = false;
  IntegratorSettings integrator;

  /// Everything in `subsection Multibody` except the name lists (and its subsection Integrator).
  static void declare_parameters(dealii::ParameterHandler &prm);
  static SimulationSettings parse_parameters(dealii::ParameterHandler &prm);
};
} // namespace flextrack::multibody
