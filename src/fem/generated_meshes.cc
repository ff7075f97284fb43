// The generated shapes of a solid: a box and a circular cylinder, with named node sets of their
// faces, as SolidMesh values (the 20-node geometry of the cylinder's curved hull included).
#include <fem/solid_mesh.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <cmath>
#include <set>
#include <sstream>

namespace flextrack::fem
{
using namespace dealii;

std::unique_ptr<SolidMesh> generate_box(const Point<3> &size, const std::array<unsigned int, 3> &n)
{
  auto mesh = std::make_unique<SolidMesh>();
  std::ostringstream d;
  d << "box " << size[0] << " x " << size[1] << " x " << size[2] << " m, " << n[0] << " x " << n[1] << " x " << n[2]
    << " cells";
  mesh->source = d.str();
  GridGenerator::subdivided_hyper_rectangle(mesh->triangulation, {n[0], n[1], n[2]}, Point<3>(), size);
  const auto &x = mesh->triangulation.get_vertices();
  const char *names[6] = {"XMIN", "XMAX", "YMIN", "YMAX", "ZMIN", "ZMAX"};
  auto on_face = [&](const Point<3> &p, unsigned int f) {
    const unsigned int axis = f / 2;
    return std::abs(p[axis] - (f % 2 ? size[axis] : 0.0)) <= 1e-12 * size.norm();
  };
  std::set<std::pair<unsigned int, unsigned int>> edges;
  for (const auto &cell : mesh->triangulation.active_cell_iterators())
    for (unsigned int l = 0; l < 12; ++l)
      {
        const auto key = ordered_edge(cell->line(l)->vertex_index(0), cell->line(l)->vertex_index(1));
        edges.insert({key.first, key.second});
      }
  for (unsigned int f = 0; f < 6; ++f)
    {
      auto &set = mesh->node_sets[names[f]];
      for (unsigned int v = 0; v < x.size(); ++v)
        if (on_face(x[v], f)) set.push_back(MeshNode{true, v, {0, 0}});
      for (const auto &e : edges)
        if (on_face(x[e.first], f) && on_face(x[e.second], f)) set.push_back(MeshNode{false, 0, e});
    }
  for (unsigned int c = 0; c < mesh->triangulation.n_active_cells(); ++c)
    mesh->element_labels.push_back("cell " + std::to_string(c + 1));
  return mesh;
}

std::unique_ptr<SolidMesh> generate_cylinder(const double radius, const double length, const unsigned int n_axial)
{
  auto mesh = std::make_unique<SolidMesh>();
  std::ostringstream d;
  d << "cylinder R = " << radius << " m, L = " << length << " m, " << n_axial << " cells along the axis";
  mesh->source = d.str();
  Triangulation<3> &tria = mesh->triangulation;
  GridGenerator::subdivided_cylinder(tria, n_axial, radius, length / 2);
  GridTools::shift(Point<3>(length / 2, 0, 0), tria);
  // Mid-side nodes from deal.II's cylinder manifolds (the hull's are on the circle); after that
  // the 20-node geometry carries the shape, so the manifolds are dropped.
  std::set<std::pair<unsigned int, unsigned int>> edges;
  for (const auto &cell : tria.active_cell_iterators())
    for (unsigned int l = 0; l < 12; ++l)
      {
        const auto key = ordered_edge(cell->line(l)->vertex_index(0), cell->line(l)->vertex_index(1));
        if (edges.insert(key).second) mesh->midside[key] = cell->line(l)->center(true);
      }
  // Node sets from the boundary ids of GridGenerator::cylinder: 0 hull, 1 x = 0, 2 x = L.
  const char *names[3] = {"HULL", "XMIN", "XMAX"};
  std::map<std::string, std::set<MeshNode>> sets;
  for (const auto &cell : tria.active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() <= 2)
        {
          auto &set = sets[names[cell->face(f)->boundary_id()]];
          for (unsigned int v = 0; v < 4; ++v) set.insert(MeshNode{true, cell->face(f)->vertex_index(v), {0, 0}});
          for (unsigned int l = 0; l < 4; ++l)
            set.insert(MeshNode{false, 0, ordered_edge(cell->face(f)->line(l)->vertex_index(0),
                                                       cell->face(f)->line(l)->vertex_index(1))});
        }
  for (const auto &[name, nodes] : sets) mesh->node_sets[name].assign(nodes.begin(), nodes.end());
  tria.reset_all_manifolds();
  tria.set_all_manifold_ids(numbers::flat_manifold_id);
  for (unsigned int c = 0; c < tria.n_active_cells(); ++c) mesh->element_labels.push_back("cell " + std::to_string(c + 1));
  return mesh;
}
} // namespace flextrack::fem
