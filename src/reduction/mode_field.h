// Mode fields along an arm: every mode's displacement u and section rotation theta (body axes)
// and their arc-length derivatives at any s, for contacts that slide along the arm.
//
// The data are the FE nodal values of each cell (degree p Lagrange on the reference nodes xi_j),
// so nothing needs the FE model at run time. Evaluation finds the cell by bisection over the
// cell boundaries (O(log n_cells), no element search) and then costs O(p n_modes).
//  - Interpolation::finite_element: the FE field itself, exact but only C0: the slope jumps at
//    element boundaries (by the FE discretisation error).
//  - Interpolation::smoothed (default): the FE field plus, within a blend zone of a quarter cell
//    at each end, the C1 correction h a psi(x) that turns the cell's end slope into the vertex
//    slope (the mean of the FE slopes of the two cells that meet there): psi(x) = x (1 - x/b)^2
//    for x < b = 1/4, 0 beyond; a = vertex slope - end slope. Values at vertices and the FE field
//    in the middle half of each cell are kept; the slope is continuous (C1), so a contact's
//    tangent moves smoothly across element boundaries and the integrator sees no kink. The
//    change is at most (4 b / 27) h |a| (b = 1/4), i.e. 3.7 % of h times the slope jump.
#pragma once

#include <geometry/curve.h>
#include <geometry/section_frame.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::reduction
{
struct ArmModeData
{
  std::string name;
  unsigned int n_modes = 0;
  std::vector<double> cell_s;    ///< cell boundaries [m], n_cells + 1, ascending, from 0 to L
  std::vector<double> xi;        ///< reference node coordinates in [0, 1], p + 1 (0 and 1 first)
  std::vector<double> positions; ///< undeformed node positions [m]: ((cell (p+1) + j) 3 + d)
  std::vector<double> values;    ///< ((cell (p+1) + j) n_modes + k) 6 + c: (u_x, u_y, u_z, theta_x, theta_y, theta_z)
  /// The exact centre line y(s) (body axes) and section frame of the arm, for contacts that slide
  /// along it (multibody track joints); null when the reduced body does not know them.
  std::shared_ptr<const geometry::Curve> curve;
  std::shared_ptr<const geometry::SectionFrame> frame;
  /// The arm's curve and section-frame parameters as parameter-file text (what rebuilds curve and
  /// frame when the reduced body is read from its file).
  std::string geometry_parameters;
  /// The cross-section's outline for drawing: (y, z) corners [m] in the section axes (section
  /// frame y axis, tangent x y axis), counter-clockwise (fem::CrossSection::outline).
  std::vector<std::array<double, 2>> section_outline;
  /// Stations along the arm where the reduction applied track loads (Reduction/Track arms and
  /// Track stations); 0: the arm has no track modes, so a contact sliding on it deforms it only
  /// through the normal and interface modes.
  unsigned int track_stations = 0;
  unsigned int n_cells() const { return cell_s.size() - 1; }
  double length() const { return cell_s.back(); }
};

class ArmModeField
{
public:
  enum class Interpolation { finite_element, smoothed };
  explicit ArmModeField(ArmModeData data, Interpolation interpolation = Interpolation::smoothed);

  /// value[k * 6 + c] and slope[k * 6 + c] (d/ds, per metre) of mode k, component c at arc
  /// length @p s; throws std::out_of_range (naming s and L) outside [0, L].
  void evaluate(double s, double *value, double *slope) const;
  const ArmModeData &data() const { return d; }

private:
  /// Cell of s and its reference coordinate.
  std::pair<unsigned int, double> locate(double s) const;
  void fe_evaluate(unsigned int cell, double x, double *value, double *slope) const;
  ArmModeData d;
  Interpolation interpolation;
  unsigned int p;
  std::vector<double> vertex_slope; // per vertex (n_cells + 1), n_modes * 6, d/ds
  static constexpr double blend = 0.25; // blend zone, fraction of a cell
  std::vector<double> end_slope;    // per cell, FE slope at its start and end, 2 n_modes * 6
};
} // namespace flextrack::reduction
