// The VTU/PVD animation of a multibody run: one animation_NNNNN.vtu per frame with every body
// drawn in global coordinates, and animation.pvd listing the frames with their times (open it in
// ParaView and press play). Binary (base64) VTU, readable by ParaView and VisIt.
//   flexible body: the reduced body's drawing surface (quadratic quads of the solid), its arms as
//                  tubes of their cross-section outline (a 16-gon, a rectangle), and its point
//                  masses as cubes, all deformed by its modes, x = R + A (x0 + sum_k u_k eta_k);
//                  a tube ring and a cube turn with the section / interface rotation of the modes;
//   rigid body:    the box of equal mass and principal moments about its centre of mass
//                  (sides a_i = sqrt(6 (J_j + J_k - J_i) / m), along the body axes; off-diagonal
//                  products of inertia are left out of the picture); a flexible body made rigid
//                  is drawn with its undeformed surface.
// Point-like things (a slider given as a point mass, a body of zero inertia, a light point mass)
// would vanish at the scale of the scene: no drawn side is smaller than 3 % of the largest body
// and twice the largest arm section, and a point mass is drawn as the steel cube of its mass
// (side (m / 7850 kg/m^3)^(1/3)) if that is larger.
// Data: point fields "displacement" (elastic, global axes [m]) and "velocity" (global [m/s]);
// cell data "body" numbers the bodies (1, 2, ... in the order of Multibody/Bodies; the comment
// at the top of each file and the log name them); field data "TimeValue" [s].
#pragma once

#include <io/output_folder.h>
#include <multibody/system.h>

#include <deal.II/base/point.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace flextrack::io
{
class AnimationWriter
{
public:
  /// The drawings of the bodies of @p system (built once).
  explicit AnimationWriter(const multibody::System &system);
  /// Writes the frame at time @p t (staged in @p folder).
  void add_frame(double t, const dealii::Vector<double> &y, OutputFolder &folder);
  /// animation.pvd, after the last frame.
  void finish(OutputFolder &folder) const;
  unsigned int n_frames() const { return times.size(); }
  /// What is drawn, for the log (one line per body).
  std::string description() const;
  /// The smallest side drawn for a point-like body [m].
  double smallest_side() const { return min_side; }

  /// The cells of one frame as VTK types (for tests): 9 quad, 23 quadratic quad, 7 polygon, 3 line.
  static constexpr unsigned char vtk_line = 3, vtk_polygon = 7, vtk_quad = 9, vtk_quadratic_quad = 23;

private:
  struct Drawing
  {
    unsigned int body = 0;                        ///< index in the system
    std::vector<dealii::Point<3>> points;         ///< body axes, undeformed
    std::vector<double> point_modes;              ///< (k P + i) 3 + d; empty: drawn rigid
    std::vector<std::vector<unsigned int>> cells; ///< point indices
    std::vector<unsigned char> types;             ///< VTK cell types
    std::string what;                             ///< for the log
  };
  /// Grows d.point_modes for the points from @p first on (added to d.points), @p n modes, the
  /// new points' translations given by @p mode(k, point).
  void append_point_modes(Drawing &d, unsigned int first, unsigned int n,
                          const std::function<multibody::Vector3(unsigned int k, unsigned int i)> &mode) const;
  void add_surface(Drawing &d, const reduction::ReducedBody &reduced, bool with_modes) const;
  void add_tube(Drawing &d, const reduction::ArmModeData &arm, unsigned int n_modes, bool with_modes) const;
  /// A box of @p sides along the body axes centred at @p centre; with @p modes (6 x n: the
  /// translation and rotation of the point in each mode), its corners follow them.
  void add_box(Drawing &d, const dealii::Point<3> &centre, std::array<double, 3> sides,
               const dealii::FullMatrix<double> *modes) const;
  const multibody::System &system;
  std::vector<Drawing> drawings;
  double min_side = 0;
  std::string body_legend; ///< "1 = base, 2 = sleeve, ..."
  std::vector<double> times;
};
} // namespace flextrack::io
