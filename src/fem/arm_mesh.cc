#include <fem/arm_mesh.h>

#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <algorithm>
#include <cmath>

namespace flextrack::fem
{
using dealii::Point;

CurveManifold::CurveManifold(std::shared_ptr<const geometry::Curve> c,
                             std::shared_ptr<const std::map<std::array<double, 3>, double>> known)
  : curve(std::move(c)), known_points(std::move(known))
{
  const int n = 1025;
  samples.reserve(n);
  for (int i = 0; i < n; ++i)
    samples.push_back(curve->position(curve->length() * i / (n - 1)));
}

std::unique_ptr<dealii::Manifold<1, 3>> CurveManifold::clone() const
{
  return std::make_unique<CurveManifold>(curve, known_points);
}

double CurveManifold::pull_back(const Point<3> &p) const
{
  // Mesh vertices (the points mappings pull back) are found exactly, without a search.
  if (known_points)
    if (const auto it = known_points->find({{p[0], p[1], p[2]}}); it != known_points->end())
      return it->second;
  const double L = curve->length();
  std::size_t best = 0;
  for (std::size_t i = 1; i < samples.size(); ++i)
    if (samples[i].distance_square(p) < samples[best].distance_square(p)) best = i;
  double s = L * best / (samples.size() - 1);
  // Newton on f(s) = (y(s) - p) . y'(s) = 0, f' = 1 + (y - p) . y''.
  for (int it = 0; it < 30; ++it)
    {
      const auto g = curve->geometry(s);
      const auto d = g.position - p;
      const double step = (d * g.tangent) / (1 + d * g.derivative[1]);
      s = std::clamp(s - step, 0.0, L);
      if (std::abs(step) < 1e-15 * L) break;
    }
  return s;
}

Point<3> CurveManifold::get_new_point(const dealii::ArrayView<const Point<3>> &points,
                                      const dealii::ArrayView<const double> &weights) const
{
  const double L = curve->length();
  const double first = pull_back(points[0]);
  double s = 0;
  for (unsigned int i = 0; i < points.size(); ++i)
    {
      double si = i == 0 ? first : pull_back(points[i]);
      if (curve->is_closed()) // unwrap across the seam s = 0 = L
        si += L * std::round((first - si) / L);
      s += weights[i] * si;
    }
  if (curve->is_closed())
    s -= L * std::floor(s / L);
  return curve->position(std::clamp(s, 0.0, L));
}

ArmMesh::ArmMesh(const Arm &arm, const unsigned int refinement) : curve(arm.curve)
{
  const double L = curve->length();
  // Stations: the ends and every support, each becomes a vertex.
  std::vector<double> stations = {0.0, L};
  for (const auto &support : arm.supports) stations.push_back(support.s);
  std::sort(stations.begin(), stations.end());
  stations.erase(std::unique(stations.begin(), stations.end(),
                             [L](double a, double b) { return std::abs(a - b) <= 1e-12 * L; }),
                 stations.end());
  stations.back() = L;

  check_arm_cell_count(arm, std::ldexp(arm.n_elements, refinement),
                       refinement > 0 ? " after " + std::to_string(refinement) + " refinements" : std::string());
  const unsigned int n_total = arm.n_elements << refinement;
  for (std::size_t k = 0; k + 1 < stations.size(); ++k)
    {
      const double a = stations[k], b = stations[k + 1];
      const unsigned int n = std::max(1u, static_cast<unsigned int>(std::lround(n_total * (b - a) / L)));
      for (unsigned int i = 0; i < n; ++i) vertex_s.push_back(a + (b - a) * i / n);
    }
  if (!curve->is_closed()) vertex_s.push_back(L);

  std::vector<Point<3>> vertices;
  for (const double s : vertex_s) vertices.push_back(curve->position(s));
  const unsigned int n_vertices = vertices.size();
  const unsigned int n_cells = curve->is_closed() ? n_vertices : n_vertices - 1;
  std::vector<dealii::CellData<1>> cells(n_cells);
  for (unsigned int c = 0; c < n_cells; ++c)
    {
      cells[c].vertices[0] = c;
      cells[c].vertices[1] = (c + 1) % n_vertices;
      cells[c].manifold_id = 0;
    }
  tria.create_triangulation(vertices, cells, dealii::SubCellData());
  auto known = std::make_shared<std::map<std::array<double, 3>, double>>();
  for (unsigned int i = 0; i < n_vertices; ++i)
    known->emplace(std::array<double, 3>{{vertices[i][0], vertices[i][1], vertices[i][2]}}, vertex_s[i]);
  tria.set_manifold(0, CurveManifold(curve, known));
}

std::pair<double, double> ArmMesh::cell_arc_lengths(const dealii::Triangulation<1, 3>::active_cell_iterator &cell) const
{
  const double s0 = vertex_s[cell->vertex_index(0)];
  double s1 = vertex_s[cell->vertex_index(1)];
  if (s1 <= s0) s1 += curve->length(); // the cell across a ring's seam
  return {s0, s1};
}

unsigned int ArmMesh::vertex_at(const double s) const
{
  // vertex_s ascends: the nearest vertex is one of the two around the first one >= s.
  const double L = curve->length();
  const double wrapped = curve->is_closed() && std::abs(s - L) <= 1e-12 * L ? 0.0 : s;
  const auto it = std::lower_bound(vertex_s.begin(), vertex_s.end(), wrapped);
  unsigned int best = std::min<std::size_t>(it - vertex_s.begin(), vertex_s.size() - 1);
  if (best > 0 && std::abs(vertex_s[best - 1] - wrapped) <= std::abs(vertex_s[best] - wrapped)) --best;
  return best;
}
} // namespace flextrack::fem
