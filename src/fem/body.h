// One flexible body as the user describes it: an optional solid part (hexahedra), any number of
// curved arms, the ties that join an arm's root to the solid, the interface points where joints
// attach (6 degrees of freedom each), and point masses. Read from "subsection Body" (plus
// "subsection Solid" and one "subsection Arm NAME" per arm) of a parameter file.
#pragma once

#include <fem/arm.h>
#include <fem/solid.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <optional>
#include <string>
#include <vector>

namespace flextrack::fem
{
/// Solid nodes that a tie or an interface point connects to: a named node set, or every node
/// within a radius of the point.
struct NodeRegion
{
  std::string node_set; ///< upper case; empty: use the radius
  double radius = 0;    ///< [m]
  std::string text;     ///< as written, for messages
};

enum class TieKind
{
  rigid,       ///< the region moves rigidly with the arm root (RBE2-like; stiffens the region)
  distributing ///< the arm root follows the region's mean motion (RBE3-like; adds no stiffness)
};

/// The root (s = 0) of an arm tied to a region of the solid.
struct ArmTie
{
  std::string arm;
  TieKind kind = TieKind::rigid;
  NodeRegion region;
};

/// A named point with 6 degrees of freedom (3 displacements, 3 small rotations) where joints
/// attach: either the node of an arm at arc length s, or a point on the solid tied rigidly to
/// the solid nodes of a region.
struct InterfacePoint
{
  std::string name;
  std::string arm; ///< empty: a point on the solid
  double s = 0;    ///< [m], on the arm
  dealii::Point<3> position; ///< [m], on the solid
  NodeRegion region;         ///< on the solid
};

/// A rigid point mass at an interface point: mass [kg] and inertia tensor about the point
/// [kg m^2], body axes.
struct PointMass
{
  std::string interface;
  double mass = 0;
  dealii::Tensor<2, 3> inertia;
};

struct Body
{
  std::optional<Solid> solid;
  std::vector<std::string> arm_names;
  std::vector<Arm> arms;
  std::vector<ArmTie> ties;
  std::vector<InterfacePoint> interfaces;
  /// Points whose motion is reported (and exported) without attaching anything: arm nodes, or
  /// points on the solid that follow a region's mean motion without stiffening it.
  std::vector<InterfacePoint> output_points;
  std::vector<PointMass> point_masses;

  /// Index of the arm called @p name, or -1.
  int arm_index(const std::string &name) const;
  /// Index of the interface called @p name, or -1.
  int interface_index(const std::string &name) const;

  /// The arm names listed in "Body/Arms" (first pass of a two-pass read: each name needs its
  /// own subsection declared before the file can be parsed strictly).
  static void declare_arm_list(dealii::ParameterHandler &prm);
  static std::vector<std::string> parse_arm_list(dealii::ParameterHandler &prm);
  /// Declares Body, Solid and "Arm NAME" for each of @p arm_names.
  static void declare_parameters(dealii::ParameterHandler &prm, const std::vector<std::string> &arm_names);
  /// @p solid_described: the file has a 'subsection Solid' ('Solid = auto' then means a solid part).
  static Body parse_parameters(dealii::ParameterHandler &prm, const std::string &directory, bool solid_described = true);
};
} // namespace flextrack::fem
