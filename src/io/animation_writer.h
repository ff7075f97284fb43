// The VTU/PVD animation of a multibody run: one animation_NNNNN.vtu per frame with every body
// drawn in global coordinates, and animation.pvd listing the frames with their times (open it in
// ParaView and press play).
//   flexible body: the reduced body's drawing surface (quadratic quads) and arm centre lines,
//                  deformed by its modes, x = R + A (x0 + sum_k u_k eta_k);
//   rigid body:    the box of equal mass and principal moments about its centre of mass
//                  (sides a_i = sqrt(6 (J_j + J_k - J_i) / m), along the body axes; off-diagonal
//                  products of inertia are left out of the picture); a flexible body made rigid
//                  is drawn with its undeformed surface.
// Cell data "body" numbers the bodies (1, 2, ... in the order of Multibody/Bodies).
#pragma once

#include <io/output_folder.h>
#include <multibody/system.h>

#include <deal.II/base/point.h>
#include <deal.II/lac/vector.h>

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

private:
  struct Drawing
  {
    unsigned int body = 0;                           ///< index in the system
    std::vector<dealii::Point<3>> points;            ///< body axes, undeformed
    std::vector<double> point_modes;                 ///< (k P + i) 3 + d, empty for rigid drawings
    std::vector<std::vector<unsigned int>> cells;    ///< point indices
    std::vector<unsigned int> types;                 ///< VTK cell types
  };
  void add_box(unsigned int body, const reduction::InertiaInvariants &inv);
  void add_surface(unsigned int body, const reduction::ReducedBody &reduced, bool with_modes);
  const multibody::System &system;
  std::vector<Drawing> drawings;
  std::vector<double> times;
};
} // namespace flextrack::io
