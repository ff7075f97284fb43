// The mesh of an arm: a Triangulation<1,3> whose vertices lie on the exact centre line at known
// arc lengths, with a manifold that places every new point (mapping support points, output
// subdivisions) on the exact curve.
#pragma once

#include <fem/arm.h>

#include <deal.II/grid/manifold.h>
#include <deal.II/grid/tria.h>

#include <array>
#include <map>
#include <utility>
#include <vector>

namespace flextrack::fem
{
/// Manifold of a centre line: points are pulled back to their arc length, averaged there
/// (across the seam of a closed curve), and pushed forward onto the curve.
class CurveManifold : public dealii::Manifold<1, 3>
{
public:
  /// @p known: points with their arc lengths (the mesh vertices), looked up before searching.
  explicit CurveManifold(std::shared_ptr<const geometry::Curve> curve,
                         std::shared_ptr<const std::map<std::array<double, 3>, double>> known = {});
  std::unique_ptr<dealii::Manifold<1, 3>> clone() const override;
  dealii::Point<3> get_new_point(const dealii::ArrayView<const dealii::Point<3>> &points,
                                 const dealii::ArrayView<const double> &weights) const override;
  /// Arc length of the curve point nearest to @p p.
  double pull_back(const dealii::Point<3> &p) const;

private:
  std::shared_ptr<const geometry::Curve> curve;
  std::shared_ptr<const std::map<std::array<double, 3>, double>> known_points;
  std::vector<dealii::Point<3>> samples; // positions at s_i = i L / (n - 1)
};

class ArmMesh
{
public:
  /// Mesh with n_elements * 2^refinement cells; every support is a vertex.
  ArmMesh(const Arm &arm, unsigned int refinement);

  const dealii::Triangulation<1, 3> &triangulation() const { return tria; }
  /// Arc lengths [m] of a cell's first and second vertex (second > first, also at a ring's seam).
  std::pair<double, double> cell_arc_lengths(const dealii::Triangulation<1, 3>::active_cell_iterator &cell) const;
  /// Vertex index at arc length s (a support station).
  unsigned int vertex_at(double s) const;
  unsigned int n_cells() const { return tria.n_active_cells(); }

private:
  std::shared_ptr<const geometry::Curve> curve;
  dealii::Triangulation<1, 3> tria;
  std::vector<double> vertex_s;
};
} // namespace flextrack::fem
