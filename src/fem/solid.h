// A 3D elastic body meshed with hexahedra, read from "subsection Solid" of a parameter file.
#pragma once

#include <fem/material.h>
#include <fem/solid_mesh.h>

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <string>
#include <vector>

namespace flextrack::fem
{
enum class SolidElement { hex20, hex8, hex27 };

/// Fix displacement components on a node set (by name) or on the plane "x = value" etc.
struct SolidSupport
{
  std::string node_set;      ///< upper-case set name; empty if a plane is given
  int plane_axis = -1;       ///< 0, 1, 2 for x, y, z planes
  double plane_position = 0; ///< [m]
  std::array<bool, 3> fixed{{true, true, true}};
  std::string text;          ///< as written, for messages
};

struct Solid
{
  std::shared_ptr<const SolidMesh> mesh;
  Material material;
  SolidElement element = SolidElement::hex20;
  unsigned int gauss_points = 3; ///< per direction: 3 = full (as CalculiX C3D20), 2 = reduced
  std::vector<SolidSupport> supports;

  static void declare_parameters(dealii::ParameterHandler &prm);
  static Solid parse_parameters(dealii::ParameterHandler &prm, const std::string &directory);
};
/// The place of a support as written before ':' in Solid/Supports: a node set (upper-cased; not
/// checked against a mesh here) or a plane 'x = value' [m]; InputError naming @p entry for a
/// malformed plane. The components are left unset.
SolidSupport parse_support_place(const std::string &place, const std::string &entry);
/// Whether @p a and @p b act at the same place (the same node set, or the same plane to 1e-12).
bool same_place(const SolidSupport &a, const SolidSupport &b);
/// Refuses a mesh of @p cells hexahedra (after any refinement) beyond 1000000 cells or beyond a
/// lower estimate of the memory it needs on this computer, before anything is allocated:
/// InputError naming @p entry, with the estimate.
void check_solid_cell_count(double cells, SolidElement element, const std::string &entry);
} // namespace flextrack::fem
