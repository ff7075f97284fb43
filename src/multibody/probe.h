// Probes: sensors that read a marker for output (Exudyn's sensors, Chrono's probes). A probe sits
// at a point of a body (any point of a rigid body, an interface of a flexible body, which then
// moves with its mode shapes) and gives that point's position and velocity, in global axes or
// in the floating frame of a chosen body (e.g. a beam's tip seen from the hub):
//   global:        r,                      r' = J_position v
//   body frame F:  x = A_F^T (r - R_F),    x' = A_F^T (r' - R_F') - omega_F x x
// (omega_F in F's axes): x' is the rate of change of x as an observer fixed in F sees it.
//
// Parameters (`subsection Probe NAME`): Body, Position [m] (global, at the initial
// configuration), Interface (flexible body), Frame (global or a body name).
#pragma once

#include <multibody/joint_table.h>
#include <multibody/marker.h>
#include <multibody/system.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <string>

namespace flextrack::multibody
{
struct ProbeValues
{
  Vector3 position; ///< [m]
  Vector3 velocity; ///< [m/s]
};

class Probe
{
public:
  /// @p frame: the body in whose floating frame the values are given; nullptr: global axes.
  Probe(std::string name, std::unique_ptr<Marker> marker, const FloatingBody *frame);
  const std::string &name() const { return probe_name; }
  /// "global" or the frame body's name.
  std::string frame_name() const;
  ProbeValues evaluate(const System &system, const dealii::Vector<double> &y) const;

  static void declare_parameters(dealii::ParameterHandler &prm);
  /// The probe of the current subsection; InputError naming "Probe NAME/..." for bad input.
  static std::unique_ptr<Probe> create(const std::string &name, dealii::ParameterHandler &prm, const BodyLookup &bodies);

private:
  std::string probe_name;
  std::unique_ptr<Marker> marker;
  const FloatingBody *frame;
};
} // namespace flextrack::multibody
