// A watch on runs that leave what their model can hold (issue 24, item 7).
//
// A reduced flexible body is linear in its modal coordinates: its elastic displacement must stay
// small against the body. A spin-up beam without geometric stiffening, a resonance without
// damping or a load far beyond the body's strength let the modal coordinates grow without bound,
// and the run used to end "completed" with a tip 1.4e7 m away. The watch compares, at every
// output row, each flexible body's largest elastic displacement over its drawing points and
// interfaces with the body's own size; the run stops when it is larger, naming the body, the
// time and the likely cause.
#pragma once

#include <multibody/system.h>

#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace flextrack::multibody
{
class GrowthWatch
{
public:
  /// Watches every flexible body (with modes) of @p system; the system must outlive the watch.
  explicit GrowthWatch(const System &system);

  /// Empty while every watched body's elastic displacement at @p y is within its size; otherwise
  /// the sentence that says what grew, when, how far, and what to change.
  std::string check(double t, const dealii::Vector<double> &y) const;

  /// The largest elastic displacement [m] of body @p b (an index of the system) at @p y, and the
  /// point (body frame, undeformed) where it is; 0 for a body without modes.
  double largest_displacement(unsigned int b, const dealii::Vector<double> &y, dealii::Point<3> *where = nullptr) const;

  /// A body's elastic displacement may reach this times its size [-].
  static constexpr double size_fraction = 1.0;

private:
  struct Watched
  {
    unsigned int body;
    double size; ///< diagonal of the bounding box of its points and interfaces [m]
    /// Each mode's largest translation over the points and interfaces [m per modal unit]:
    /// sum_k mode_extent[k] |eta_k| bounds the largest displacement from above, so the scan of
    /// every point (1.3 % of the laser robot's run, thousands of surface points x 44 modes at
    /// each output row) is needed only when the bound exceeds the limit.
    std::vector<double> mode_extent;
  };
  const System &system;
  std::vector<Watched> watched;
};
} // namespace flextrack::multibody
