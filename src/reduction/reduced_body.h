// Everything a multibody run, an exporter or a viewer needs of one reduced flexible body, and
// nothing of its FE model: the reduced matrices, the inertia invariants, the interfaces' mode
// shapes, the mode fields along every arm, and a surface to draw the deformed body with.
// Written to and read from HDF5 by io/reduced_body_file.h (layout in doc/reduced_body_file.md).
#pragma once

#include <reduction/inertia_invariants.h>
#include <reduction/mode_field.h>

#include <deal.II/base/point.h>
#include <deal.II/lac/full_matrix.h>

#include <array>
#include <string>
#include <vector>

namespace flextrack::reduction
{
struct ReducedBody
{
  // Provenance
  std::string input_hash;  ///< hash of every input (io/body_scene.h)
  std::string method;      ///< "craig bampton" or "free interface"
  std::string source;      ///< the parameter file
  unsigned int n_full_dofs = 0, n_body_dofs = 0;
  unsigned int n_normal = 0, n_interface = 0, n_track = 0;

  // Reduced model (n = number of modes)
  dealii::FullMatrix<double> stiffness, mass, damping; ///< n x n [N/m], [kg], [N s/m] per modal unit
  std::vector<double> frequencies_hz;                  ///< n, of the reduced model
  /// 12 x (n x n), or empty: geometric stiffness of unit inertial loads (ReducedBasis).
  std::vector<dealii::FullMatrix<double>> geometric_stiffness;
  InertiaInvariants invariants;

  struct Interface
  {
    std::string name;
    dealii::Point<3> position;      ///< [m], body frame
    dealii::FullMatrix<double> modes; ///< 6 x n: (u_x, u_y, u_z, theta_x, theta_y, theta_z) of each mode
  };
  std::vector<Interface> interfaces;
  std::vector<Interface> output_points; ///< same layout; reported and exported, nothing attaches
  std::vector<ArmModeData> arms;

  // Drawing: points of the surface (solid) and centre lines (arms), and each mode's translation
  std::vector<dealii::Point<3>> points;
  std::vector<std::array<unsigned int, 8>> quads; ///< quadratic quads, VTK order (corners, then mid-sides)
  std::vector<std::array<unsigned int, 2>> lines; ///< arm centre-line segments
  std::vector<double> point_modes;                ///< (k P + i) 3 + d, P = points.size()
  /// Point masses, drawn as cubes at their interface: (index in interfaces, mass [kg]).
  std::vector<std::pair<unsigned int, double>> point_masses;

  unsigned int n_modes() const { return stiffness.m(); }
};

/// K_r + sum_c coefficient_c G_c: the reduced stiffness under the inertial loads of a body frame
/// turning at @p omega [rad/s], its origin accelerating at @p acceleration [m/s^2] (minus gravity
/// for a body under gravity g), turning faster at @p angular_acceleration [rad/s^2], all in body
/// axes. Without geometric stiffness in the body, K_r.
dealii::FullMatrix<double> stiffness_with_inertial_loads(const ReducedBody &body, const dealii::Tensor<1, 3> &omega,
                                                         const dealii::Tensor<1, 3> &acceleration,
                                                         const dealii::Tensor<1, 3> &angular_acceleration);

} // namespace flextrack::reduction
