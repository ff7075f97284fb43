// Everything that defines one curved flexible arm: centre line, section frame, cross-section,
// material, supports and mesh settings, read from "subsection Arm" of a parameter file.
#pragma once

#include <fem/cross_section.h>
#include <fem/material.h>
#include <geometry/curve.h>
#include <geometry/curve_library.h>
#include <geometry/section_frame.h>

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <vector>

namespace flextrack::fem
{
enum class SupportKind { free, pinned, clamped };

/// A support at arc length s: pinned fixes the 3 displacements, clamped also the 3 rotations.
struct Support
{
  double s;
  SupportKind kind;
};

/// Most cells of an arm's mesh, after any refinement: 200000 cells of degree 3 are 3.6e6 degrees
/// of freedom, about 7 GiB for the matrices, their factorisation and the Lanczos vectors.
constexpr double max_arm_cells = 200000;
/// Most intermediate supports of one arm.
constexpr unsigned int max_intermediate_supports = 1000;

struct Arm
{
  std::shared_ptr<const geometry::Curve> curve;
  std::shared_ptr<const geometry::SectionFrame> frame;
  CrossSection section;
  Material material;
  std::vector<Support> supports;
  unsigned int n_elements = 16; ///< on the coarsest mesh
  unsigned int degree = 2;      ///< polynomial degree of the beam element, 1..3
  std::string section_name = "Arm"; ///< its subsection ("Arm", or "Arm NAME" in a body), for messages
  /// Parameter-file text of "subsection Curve" (the chosen kind only) and "subsection Section
  /// frame" with the values read, self-contained (a spline's points inline, no file names): what
  /// rebuilds curve and frame exactly, e.g. from a reduced body file. Empty for an arm built in code.
  std::string geometry_parameters;

  /// The supports for a log: "start clamped, end free" and any intermediate "s = 0.5 m pinned".
  std::string supports_text() const;

  /// Declares "subsection @p section" (a body's arms are "Arm NAME").
  static void declare_parameters(dealii::ParameterHandler &prm, const std::string &section = "Arm");
  /// Reads "subsection @p section"; relative file names are taken from @p directory.
  static Arm parse_parameters(dealii::ParameterHandler &prm, const std::string &directory,
                              const std::string &section = "Arm");
};

SupportKind parse_support_kind(const std::string &text, const std::string &entry);

/// Refuses a mesh of @p n_cells cells (@p how: "" or " after 3 refinements") if it exceeds
/// max_arm_cells: InputError naming the arm's "Mesh/Number of elements", with the memory the
/// mesh would need (about 2 KiB per degree of freedom, measured).
void check_arm_cell_count(const Arm &arm, double n_cells, const std::string &how);
} // namespace flextrack::fem
