#include <fem/fe_serendipity.h>
#include <fem/solid_mesh.h>
#include <io/input_error.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>
#include <sstream>

namespace flextrack::fem
{
using namespace dealii;

Point<3> SolidMesh::line_midpoint(const unsigned int v0, const unsigned int v1) const
{
  const auto key = ordered_edge(v0, v1);
  if (const auto it = midside.find({key.first, key.second}); it != midside.end()) return it->second;
  return 0.5 * (triangulation.get_vertices()[v0] + triangulation.get_vertices()[v1]);
}

Point<3> SolidMesh::position(const MeshNode &node) const
{
  return node.is_vertex ? triangulation.get_vertices()[node.vertex] : line_midpoint(node.edge.first, node.edge.second);
}

namespace
{
std::string upper(std::string s)
{
  for (auto &c : s) c = std::toupper(static_cast<unsigned char>(c));
  return s;
}
std::string trim(const std::string &s)
{
  const auto b = s.find_first_not_of(" \t\r"), e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}
/// Value of KEY=VALUE in a keyword line ("" if absent).
std::string option(const std::string &keyword_line, const std::string &key)
{
  std::istringstream in(keyword_line);
  std::string item;
  while (std::getline(in, item, ','))
    {
      const auto eq = item.find('=');
      if (eq != std::string::npos && upper(trim(item.substr(0, eq))) == key) return trim(item.substr(eq + 1));
    }
  return "";
}
std::vector<long> integers(const std::string &line, const std::string &where)
{
  std::vector<long> v;
  std::istringstream in(line);
  std::string item;
  while (std::getline(in, item, ','))
    {
      item = trim(item);
      if (item.empty()) continue;
      try { v.push_back(std::stol(item)); }
      catch (...) { throw InputError("", where + ": '" + item + "' is not an integer"); }
    }
  return v;
}

// Abaqus hexahedron corners 1..8 -> deal.II's lexicographic vertex numbers.
constexpr unsigned int abaqus_to_deal[8] = {0, 1, 3, 2, 4, 5, 7, 6};
// Abaqus mid-side nodes 9..20 lie on these corner pairs (Abaqus numbering, 0-based).
constexpr unsigned int abaqus_edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                              {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

struct RawElement
{
  long id;
  int line;
  std::vector<long> nodes;
};
} // namespace

namespace
{
/// Throws if the 20-node map with nodes @p x (deal.II order) is inverted or degenerate at a
/// 3x3x3 Gauss point.
void check_element(const std::array<Point<3>, 20> &x, const std::string &label, const std::string &source,
                   const std::string &entry)
{
  // Shape function gradients at the 27 Gauss points, tabulated once.
  static const std::vector<std::array<Tensor<1, 3>, 20>> gradients = [] {
    const SerendipityPolynomials N;
    const QGauss<3> gauss(3);
    std::vector<std::array<Tensor<1, 3>, 20>> g(gauss.size());
    for (unsigned int q = 0; q < gauss.size(); ++q)
      for (unsigned int i = 0; i < 20; ++i) g[q][i] = N.compute_grad(i, gauss.point(q));
    return g;
  }();
  {
    {
      double smallest = std::numeric_limits<double>::max(), largest = 0;
      for (const auto &grad : gradients)
        {
          Tensor<2, 3> J;
          for (unsigned int i = 0; i < 20; ++i) J += outer_product(x[i], grad[i]);
          smallest = std::min(smallest, determinant(J));
          largest = std::max(largest, std::abs(determinant(J)));
        }
      if (!(smallest > 1e-10 * largest))
        {
          std::ostringstream m;
          m << label << " of '" << source << "' is inverted or degenerate: its Jacobian determinant "
            << "reaches " << smallest << " (must stay > 0); check its node order (Abaqus: corners 1-4 "
            << "counter-clockwise, 5-8 above them) and its mid-side node positions";
          throw InputError(entry, m.str());
        }
    }
  }
}
} // namespace

std::unique_ptr<SolidMesh> read_abaqus_mesh(const std::string &file, const std::string &entry)
{
  std::ifstream in(file);
  if (!in)
    throw InputError(entry, "cannot open the mesh file '" + file + "'; give an existing Abaqus/CalculiX .inp file");
  std::map<long, Point<3>> nodes;
  std::vector<RawElement> elements;
  std::map<std::string, std::vector<long>> sets;
  enum class Block { none, node, element, nset } block = Block::none;
  bool generate = false;
  std::string set_name;
  int nodes_per_element = 0;
  std::string line;
  int number = 0;
  std::vector<long> pending; // an element's node list may continue on the next line
  int pending_line = 0;
  auto where = [&](int l) { return file + ", line " + std::to_string(l); };

  while (std::getline(in, line))
    {
      ++number;
      const std::string t = trim(line);
      if (t.empty() || t.rfind("**", 0) == 0) continue;
      if (t[0] == '*')
        {
          const std::string key = upper(trim(t.substr(1, t.find(',') == std::string::npos ? std::string::npos : t.find(',') - 1)));
          block = Block::none;
          if (key == "NODE" && option(t, "NSET").empty() && true)
            block = Block::node;
          else if (key == "NODE")
            block = Block::node;
          else if (key == "ELEMENT")
            {
              const std::string type = upper(option(t, "TYPE"));
              if (type == "C3D8" || type == "C3D8R" || type == "C3D8I")
                nodes_per_element = 8;
              else if (type == "C3D20" || type == "C3D20R")
                nodes_per_element = 20;
              else
                throw InputError(entry, "unsupported element type '" + type + "' at " + where(number) +
                                 "; allowed: hexahedra C3D8, C3D8R, C3D8I, C3D20, C3D20R (tetrahedra, wedges, "
                                 "shells and beams cannot be read)");
              block = Block::element;
            }
          else if (key == "NSET")
            {
              set_name = upper(option(t, "NSET"));
              generate = upper(t).find("GENERATE") != std::string::npos;
              block = Block::nset;
            }
          continue;
        }
      if (block == Block::node)
        {
          std::istringstream fields(t);
          std::string id, x, y, z;
          std::getline(fields, id, ',');
          std::getline(fields, x, ',');
          std::getline(fields, y, ',');
          std::getline(fields, z, ',');
          try
            {
              nodes[std::stol(id)] = Point<3>(std::stod(x), std::stod(y), z.empty() ? 0.0 : std::stod(z));
            }
          catch (...)
            {
              throw InputError(entry, "a node line must be 'id, x, y, z' at " + where(number));
            }
        }
      else if (block == Block::element)
        {
          const auto v = integers(t, where(number));
          if (pending.empty()) pending_line = number;
          pending.insert(pending.end(), v.begin(), v.end());
          if (static_cast<int>(pending.size()) >= nodes_per_element + 1)
            {
              if (static_cast<int>(pending.size()) > nodes_per_element + 1)
                throw InputError(entry, "element with more than " + std::to_string(nodes_per_element) +
                                 " nodes at " + where(pending_line));
              elements.push_back({pending[0], pending_line, std::vector<long>(pending.begin() + 1, pending.end())});
              pending.clear();
            }
        }
      else if (block == Block::nset)
        {
          const auto v = integers(t, where(number));
          auto &set = sets[set_name];
          if (generate && v.size() >= 2)
            for (long k = v[0]; k <= v[1]; k += v.size() > 2 ? v[2] : 1) set.push_back(k);
          else
            set.insert(set.end(), v.begin(), v.end());
        }
    }
  if (!pending.empty())
    throw InputError(entry, "the element at " + where(pending_line) + " has too few nodes");
  if (elements.empty())
    throw InputError(entry, "'" + file + "' holds no hexahedral elements (*ELEMENT, TYPE=C3D8 or C3D20)");

  auto mesh = std::make_unique<SolidMesh>();
  mesh->source = file;
  // Vertices: the corner nodes used by elements, numbered in order of node id.
  std::map<long, unsigned int> vertex_of;
  std::vector<Point<3>> vertices;
  for (const auto &e : elements)
    for (unsigned int k = 0; k < 8; ++k)
      {
        if (!nodes.count(e.nodes[k]))
          throw InputError(entry, "element " + std::to_string(e.id) + " at " + where(e.line) + " uses node " +
                           std::to_string(e.nodes[k]) + ", which is not defined under *NODE");
        if (vertex_of.emplace(e.nodes[k], vertices.size()).second) vertices.push_back(nodes[e.nodes[k]]);
      }
  std::vector<CellData<3>> cells(elements.size());
  std::map<long, MeshNode> node_ref; // file node id -> mesh node
  for (const auto &[id, v] : vertex_of) node_ref[id] = MeshNode{true, v, {0, 0}};
  for (std::size_t c = 0; c < elements.size(); ++c)
    {
      const auto &e = elements[c];
      for (unsigned int k = 0; k < 8; ++k) cells[c].vertices[abaqus_to_deal[k]] = vertex_of[e.nodes[k]];
      for (unsigned int k = 0; k < 12; ++k)
        {
          const unsigned int a = vertex_of[e.nodes[abaqus_edges[k][0]]], b = vertex_of[e.nodes[abaqus_edges[k][1]]];
          const auto key = ordered_edge(a, b);
          if (e.nodes.size() == 20)
            {
              const long mid = e.nodes[8 + k];
              if (!nodes.count(mid))
                throw InputError(entry, "element " + std::to_string(e.id) + " at " + where(e.line) + " uses node " +
                                 std::to_string(mid) + ", which is not defined under *NODE");
              mesh->midside[key] = nodes[mid];
              node_ref[mid] = MeshNode{false, 0, key};
            }
        }
      mesh->element_labels.push_back("element " + std::to_string(e.id) + " (" + where(e.line) + ")");
    }
  for (const auto &[name, ids] : sets)
    {
      auto &set = mesh->node_sets[name];
      for (const long id : ids)
        if (const auto it = node_ref.find(id); it != node_ref.end()) set.push_back(it->second);
    }
  // Refuse inverted or degenerate elements, naming them, before deal.II sees the mesh.
  for (std::size_t c = 0; c < cells.size(); ++c)
    {
      std::array<Point<3>, 20> x;
      for (unsigned int v = 0; v < 8; ++v) x[v] = vertices[cells[c].vertices[v]];
      for (unsigned int l = 0; l < 12; ++l)
        {
          const unsigned int a = cells[c].vertices[GeometryInfo<3>::line_to_cell_vertices(l, 0)];
          const unsigned int b = cells[c].vertices[GeometryInfo<3>::line_to_cell_vertices(l, 1)];
          const auto it = mesh->midside.find(ordered_edge(a, b));
          x[8 + l] = it != mesh->midside.end() ? it->second : 0.5 * (vertices[a] + vertices[b]);
        }
      check_element(x, mesh->element_labels[c], file, entry);
    }
  mesh->triangulation.create_triangulation(vertices, cells, SubCellData());
  return mesh;
}

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


} // namespace flextrack::fem
