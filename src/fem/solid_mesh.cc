#include <fem/fe_serendipity.h>
#include <base/text.h>
#include <fem/solid_mesh.h>
#include <base/input_error.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
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
using base::trim;
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

namespace
{
/// Build the mesh from elements given with Abaqus node order (8 corners, then 12 mid-sides or
/// none), node coordinates and node sets by node id.
std::unique_ptr<SolidMesh> build_mesh(const std::string &file, const std::string &entry,
                                      std::map<long, Point<3>> &nodes, const std::vector<RawElement> &elements,
                                      const std::map<std::string, std::vector<long>> &sets)
{
  auto where = [&](int l) { return file + ", line " + std::to_string(l); };
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
  return build_mesh(file, entry, nodes, elements, sets);
}


namespace
{
// Gmsh element types (Gmsh reference manual, "MSH file format"): what they are called.
std::string gmsh_type_name(const int type)
{
  static const std::map<int, std::string> names = {
    {1, "2-node line"},     {2, "3-node triangle"},     {3, "4-node quadrangle"}, {4, "4-node tetrahedron"},
    {5, "8-node hexahedron"}, {6, "6-node prism"},      {7, "5-node pyramid"},    {8, "3-node line"},
    {9, "6-node triangle"}, {10, "9-node quadrangle"},  {11, "10-node tetrahedron"},
    {12, "27-node hexahedron"}, {13, "18-node prism"},  {14, "14-node pyramid"},  {15, "1-node point"},
    {16, "8-node quadrangle"}, {17, "20-node hexahedron"}, {18, "15-node prism"}, {19, "13-node pyramid"}};
  const auto it = names.find(type);
  return it != names.end() ? it->second : "type " + std::to_string(type);
}
// Nodes per element type; 0 for types this reader does not know.
int gmsh_nodes_per_element(const int type)
{
  static const std::map<int, int> n = {{1, 2}, {2, 3}, {3, 4}, {4, 4}, {5, 8}, {6, 6}, {7, 5}, {8, 3}, {9, 6},
                                       {10, 9}, {11, 10}, {12, 27}, {13, 18}, {14, 14}, {15, 1}, {16, 8},
                                       {17, 20}, {18, 15}, {19, 13}};
  const auto it = n.find(type);
  return it != n.end() ? it->second : 0;
}
bool gmsh_is_volume(const int type) { return type == 4 || (type >= 5 && type <= 7) || (type >= 11 && type <= 14) || type >= 17; }

// Gmsh's 20-node hexahedron lists its mid-side nodes on edges (0,1) (0,3) (0,4) (1,2) (1,5)
// (2,3) (2,6) (3,7) (4,5) (4,7) (5,6) (6,7); Abaqus' order is (0,1) (1,2) (2,3) (3,0) (4,5)
// (5,6) (6,7) (7,4) (0,4) (1,5) (2,6) (3,7). Corners agree.
constexpr unsigned int gmsh_to_abaqus_midside[12] = {0, 3, 8, 1, 9, 2, 10, 11, 4, 7, 5, 6};

/// Add a hexahedron (Gmsh order) to the elements, or refuse other volume elements.
void add_gmsh_element(const long id, const int type, const std::vector<long> &gmsh_nodes, const int line,
                      const std::string &file, const std::string &entry, std::vector<RawElement> &elements)
{
  if (type != 5 && type != 17)
    throw InputError(entry, "unsupported element: " + gmsh_type_name(type) + " (element " + std::to_string(id) +
                     ") at " + file + ", line " + std::to_string(line) +
                     "; allowed volume elements: 8-node and 20-node hexahedra (Gmsh types 5 and 17)");
  RawElement e{id, line, std::vector<long>(gmsh_nodes.begin(), gmsh_nodes.begin() + 8)};
  if (type == 17)
    {
      e.nodes.resize(20);
      for (unsigned int m = 0; m < 12; ++m) e.nodes[8 + gmsh_to_abaqus_midside[m]] = gmsh_nodes[8 + m];
    }
  elements.push_back(std::move(e));
}
} // namespace

std::unique_ptr<SolidMesh> read_gmsh_mesh(const std::string &file, const std::string &entry)
{
  std::ifstream in(file);
  if (!in)
    throw InputError(entry, "cannot open the mesh file '" + file + "'; give an existing Gmsh .msh file");
  std::map<long, Point<3>> nodes;
  std::vector<RawElement> elements;
  std::map<std::string, std::vector<long>> sets;
  std::map<std::pair<int, int>, std::string> physical_names;      // (dim, tag) -> name
  std::map<std::pair<int, int>, std::vector<int>> entity_physicals; // v4: (dim, entity) -> physical tags
  double version = 0;
  int line_number = 0;
  std::string line;
  auto next_line = [&]() {
    if (!std::getline(in, line))
      throw InputError(entry, "'" + file + "' ends early (line " + std::to_string(line_number) + "); it is not a complete Gmsh mesh");
    ++line_number;
    return std::istringstream(line);
  };
  auto fail = [&](const std::string &what) {
    throw InputError(entry, "cannot read " + file + ", line " + std::to_string(line_number) + ": " + what);
  };
  auto set_name = [&](int dim, int tag) {
    const auto it = physical_names.find({dim, tag});
    return it != physical_names.end() ? upper(it->second) : "PHYSICAL_" + std::to_string(tag);
  };
  auto add_to_sets = [&](const std::vector<int> &physicals, int dim, const std::vector<long> &element_nodes) {
    for (const int tag : physicals)
      {
        auto &set = sets[set_name(dim, tag)];
        set.insert(set.end(), element_nodes.begin(), element_nodes.end());
      }
  };

  while (std::getline(in, line))
    {
      ++line_number;
      const std::string section = trim(line);
      if (section == "$MeshFormat")
        {
          auto f = next_line();
          int binary = 0;
          f >> version >> binary;
          if (binary != 0) fail("binary .msh files are not supported; save the mesh as ASCII");
          if (!(version >= 2 && version < 3) && !(version >= 4.1 && version < 5))
            fail("MSH format version " + std::to_string(version) + " is not supported; allowed: 2.2 and 4.1 (ASCII)");
        }
      else if (section == "$PhysicalNames")
        {
          int n = 0;
          next_line() >> n;
          for (int i = 0; i < n; ++i)
            {
              auto f = next_line();
              int dim, tag;
              std::string name;
              f >> dim >> tag;
              std::getline(f, name);
              name = trim(name);
              if (name.size() >= 2 && name.front() == '"') name = name.substr(1, name.size() - 2);
              physical_names[{dim, tag}] = name;
            }
        }
      else if (section == "$Entities")
        {
          int count[4];
          auto f = next_line();
          f >> count[0] >> count[1] >> count[2] >> count[3];
          for (int dim = 0; dim < 4; ++dim)
            for (int i = 0; i < count[dim]; ++i)
              {
                auto e = next_line();
                int tag, n_physical;
                double box;
                e >> tag;
                for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) e >> box;
                e >> n_physical;
                auto &list = entity_physicals[{dim, tag}];
                for (int k = 0; k < n_physical; ++k)
                  {
                    int physical;
                    e >> physical;
                    list.push_back(std::abs(physical));
                  }
              }
        }
      else if (section == "$Nodes")
        {
          if (version < 3)
            {
              long n = 0;
              next_line() >> n;
              for (long i = 0; i < n; ++i)
                {
                  auto f = next_line();
                  long id;
                  Point<3> p;
                  if (!(f >> id >> p[0] >> p[1] >> p[2])) fail("a node line must be 'id x y z'");
                  nodes[id] = p;
                }
            }
          else
            {
              long blocks = 0, n = 0, min_tag, max_tag;
              next_line() >> blocks >> n >> min_tag >> max_tag;
              for (long b = 0; b < blocks; ++b)
                {
                  int dim, tag, parametric;
                  long count;
                  next_line() >> dim >> tag >> parametric >> count;
                  std::vector<long> ids(count);
                  for (auto &id : ids) next_line() >> id;
                  for (const long id : ids)
                    {
                      auto f = next_line();
                      Point<3> p;
                      if (!(f >> p[0] >> p[1] >> p[2])) fail("a node line must be 'x y z'");
                      nodes[id] = p;
                    }
                }
            }
        }
      else if (section == "$Elements")
        {
          if (version < 3)
            {
              long n = 0;
              next_line() >> n;
              for (long i = 0; i < n; ++i)
                {
                  auto f = next_line();
                  long id;
                  int type, n_tags;
                  f >> id >> type >> n_tags;
                  std::vector<int> tags(n_tags);
                  for (auto &t : tags) f >> t;
                  const int per = gmsh_nodes_per_element(type);
                  if (per == 0) fail("unknown element type " + std::to_string(type));
                  std::vector<long> element_nodes(per);
                  for (auto &v : element_nodes)
                    if (!(f >> v)) fail("element " + std::to_string(id) + " has too few nodes");
                  if (gmsh_is_volume(type))
                    add_gmsh_element(id, type, element_nodes, line_number, file, entry, elements);
                  else if (n_tags > 0 && tags[0] != 0)
                    add_to_sets({tags[0]}, type == 15 ? 0 : (type == 1 || type == 8) ? 1 : 2, element_nodes);
                }
            }
          else
            {
              long blocks = 0, n = 0, min_tag, max_tag;
              next_line() >> blocks >> n >> min_tag >> max_tag;
              for (long b = 0; b < blocks; ++b)
                {
                  int dim, tag, type;
                  long count;
                  next_line() >> dim >> tag >> type >> count;
                  const int per = gmsh_nodes_per_element(type);
                  if (per == 0) fail("unknown element type " + std::to_string(type));
                  for (long i = 0; i < count; ++i)
                    {
                      auto f = next_line();
                      long id;
                      f >> id;
                      std::vector<long> element_nodes(per);
                      for (auto &v : element_nodes)
                        if (!(f >> v)) fail("element " + std::to_string(id) + " has too few nodes");
                      if (dim == 3)
                        add_gmsh_element(id, type, element_nodes, line_number, file, entry, elements);
                      else if (const auto it = entity_physicals.find({dim, tag}); it != entity_physicals.end())
                        add_to_sets(it->second, dim, element_nodes);
                    }
                }
            }
        }
    }
  if (version == 0)
    throw InputError(entry, "'" + file + "' is not a Gmsh mesh (no $MeshFormat section)");
  if (elements.empty())
    throw InputError(entry, "'" + file + "' holds no hexahedra (Gmsh element types 5 or 17)");
  for (auto &[name, ids] : sets)
    {
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    }
  return build_mesh(file, entry, nodes, elements, sets);
}

std::unique_ptr<SolidMesh> read_mesh_file(const std::string &file, const std::string &entry)
{
  const std::string extension = upper(std::filesystem::path(file).extension().string());
  if (extension == ".INP") return read_abaqus_mesh(file, entry);
  if (extension == ".MSH") return read_gmsh_mesh(file, entry);
  throw InputError(entry, "cannot tell the format of '" + file + "' from its extension; allowed: .inp "
                   "(Abaqus/CalculiX) and .msh (Gmsh 2.2 or 4.1, ASCII)");
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
