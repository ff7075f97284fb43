// What the mesh readers share: the SolidMesh methods, the checks of a mesh file and of its text,
// building the triangulation from the raw elements, the element check, and read_mesh_file.
// The readers: abaqus_mesh_reader.cc, gmsh_mesh_reader.cc; the generated shapes: generated_meshes.cc.
#include <base/input_error.h>
#include <base/names.h>
#include <fem/fe_serendipity.h>
#include <fem/raw_mesh.h>
#include <fem/solid_mesh.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/grid/tria_accessor.h>
#include <deal.II/grid/tria_iterator.h>

#include <algorithm>
#include <iomanip>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
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

namespace mesh_reading
{
namespace
{
/// Lines longer than this are not a mesh file's (Abaqus allows 256 characters).
constexpr std::size_t max_line_length = std::size_t(1) << 20;

std::string hex_byte(const unsigned char c)
{
  char text[8];
  std::snprintf(text, sizeof text, "0x%02x", c);
  return text;
}

std::string kind_of_file(const std::filesystem::file_type type)
{
  switch (type)
    {
      case std::filesystem::file_type::directory: return "a directory";
      case std::filesystem::file_type::character: return "a character device (it may never end)";
      case std::filesystem::file_type::block: return "a block device";
      case std::filesystem::file_type::fifo: return "a named pipe";
      case std::filesystem::file_type::socket: return "a socket";
      default: return "of an unknown kind";
    }
}
} // namespace

std::string upper(std::string s)
{
  for (auto &c : s) c = std::toupper(static_cast<unsigned char>(c));
  return s;
}

void check_mesh_file(const std::string &file, const std::string &entry, const std::string &kind)
{
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(file, error);
  if (status.type() == fs::file_type::not_found)
    throw InputError(entry, "cannot open the mesh file '" + file + "': it does not exist; give an existing " + kind);
  if (error)
    throw InputError(entry, "cannot open the mesh file '" + file + "': " + error.message() + "; give a readable " +
                            kind);
  if (status.type() != fs::file_type::regular)
    throw InputError(entry, "the mesh file '" + file + "' is " + kind_of_file(status.type()) +
                            ", not a regular file; give an existing " + kind);
  const std::uintmax_t size = fs::file_size(file, error);
  if (error)
    throw InputError(entry, "cannot open the mesh file '" + file + "': " + error.message() + "; give a readable " +
                            kind);
  if (size > max_file_size)
    throw InputError(entry, "the mesh file '" + file + "' has " + std::to_string(size) +
                            " bytes; a mesh file may have at most 1 GiB (" + std::to_string(max_file_size) + " bytes)");
}

MeshText::MeshText(const std::string &file_name, const std::string &entry_name, const std::string &kind)
  : file(file_name), entry(entry_name)
{
  check_mesh_file(file, entry, kind);
  std::error_code error;
  size = std::filesystem::file_size(file, error);
  in.open(file, std::ios::binary);
  if (!in)
    throw InputError(entry, "cannot open the mesh file '" + file + "': " + std::strerror(errno) +
                            "; give a readable " + kind);
}

bool MeshText::next(std::string &line)
{
  line.clear();
  std::streambuf *buffer = in.rdbuf();
  bool any = false;
  for (int c; (c = buffer->sbumpc()) != std::char_traits<char>::eof();)
    {
      any = true;
      // The file's size was checked on opening; this bound holds even if it grows meanwhile.
      if (++bytes_read > max_file_size) fail_at(number + 1, "more than 1 GiB read; a mesh file may have at most 1 GiB");
      if (c == '\n') break;
      if (line.size() >= max_line_length)
        fail_at(number + 1, "a line of more than 1 MiB; this is not a mesh file (a text file of short lines)");
      line.push_back(static_cast<char>(c));
    }
  if (!any) return false;
  ++number;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (number == 1 && line.size() >= 2 &&
      ((line[0] == '\xff' && line[1] == '\xfe') || (line[0] == '\xfe' && line[1] == '\xff')))
    fail("the file is UTF-16 text; save it as ASCII (or UTF-8) text");
  if (number == 1 && line.rfind("\xef\xbb\xbf", 0) == 0) line.erase(0, 3); // a UTF-8 byte order mark
  for (const char c : line)
    {
      const auto u = static_cast<unsigned char>(c);
      if ((u < 0x20 && c != '\t' && c != '\v' && c != '\f') || u == 0x7f)
        fail("not a text file: the line holds the byte " + hex_byte(u) + " ('" + base::printable_excerpt(line, 40) +
             "'); a mesh file is ASCII text (binary and UTF-16 files cannot be read)");
    }
  return true;
}

std::string MeshText::next_or_fail()
{
  std::string line;
  if (!next(line))
    throw InputError(entry, "'" + file + "' ends early (line " + std::to_string(number) +
                            "); it is not a complete mesh");
  return line;
}

std::string MeshText::where(const int line) const { return file + ", line " + std::to_string(line); }

void MeshText::fail(const std::string &what) const { fail_at(number, what); }

void MeshText::fail_at(const int line, const std::string &what) const
{
  throw InputError(entry, "cannot read " + where(line) + ": " + what);
}

long MeshText::integer(const std::string &word, const std::string &what) const
{
  errno = 0;
  char *end = nullptr;
  const bool blank = word.empty() || std::isspace(static_cast<unsigned char>(word[0]));
  const long value = blank ? 0 : std::strtol(word.c_str(), &end, 10);
  if (end != word.c_str() + word.size() || errno == ERANGE)
    fail("'" + base::printable_excerpt(word, 30) + "' is not " + what + " (a whole number of at most 18 digits)");
  return value;
}

double MeshText::coordinate(const std::string &word, const long node) const
{
  const auto parse = [](const std::string &text, double &x) {
    char *end = nullptr;
    x = text.empty() || std::isspace(static_cast<unsigned char>(text[0])) ? 0 : std::strtod(text.c_str(), &end);
    return end ? static_cast<std::size_t>(end - text.c_str()) : 0; // characters used
  };
  double x = 0;
  std::size_t used = parse(word, x);
  if (used < word.size() && (word[used] == 'd' || word[used] == 'D')) // Fortran's 1.5D+03
    used = parse(word.substr(0, used) + 'e' + word.substr(used + 1), x);
  if (used != word.size() || word.empty())
    fail("node " + std::to_string(node) + ": '" + base::printable_excerpt(word, 30) + "' is not a number");
  if (!(std::abs(x) <= max_coordinate))
    fail("node " + std::to_string(node) + ": the coordinate '" + base::printable_excerpt(word, 30) +
         "' is not allowed; a coordinate is a finite number from -1e9 to 1e9 m");
  return x;
}

long MeshText::count(const std::string &word, const std::string &what, const std::uintmax_t bytes_per_item) const
{
  const long n = integer(word, "a count of " + what);
  const std::uintmax_t rest = size > bytes_read ? size - bytes_read : 0, most = rest / bytes_per_item;
  if (n < 0 || static_cast<std::uintmax_t>(n) > most)
    fail(std::to_string(n) + " " + what + " announced, but the rest of the file (" + std::to_string(rest) +
         " bytes) can hold at most " + std::to_string(most) + "; allowed: a count from 0 to " + std::to_string(most));
  return n;
}

void RawMesh::add_node(const MeshText &text, const long id, const Point<3> &position)
{
  const auto [it, added] = nodes.emplace(id, std::make_pair(position, text.line_number()));
  if (!added)
    text.fail("node " + std::to_string(id) + " is defined a second time (first at line " +
              std::to_string(it->second.second) + "); node numbers must be unique");
}

void RawMesh::add_element(const MeshText &text, RawElement &&element)
{
  const auto [it, added] = element_lines.emplace(element.id, element.line);
  if (!added)
    text.fail_at(element.line, "element " + std::to_string(element.id) + " is defined a second time (first at line " +
                                   std::to_string(it->second) + "); element numbers must be unique");
  elements.push_back(std::move(element));
}

void RawMesh::count_set_members(const MeshText &text, const int line, const std::size_t more)
{
  const std::size_t budget = std::max<std::size_t>(10'000'000, 64 * nodes.size());
  if (more > budget - std::min(budget, n_set_members))
    text.fail_at(line, "the node sets would hold more than " + std::to_string(budget) +
                           " members in all; allowed: at most 64 per node of the mesh (or 10000000)");
  n_set_members += more;
}

namespace
{
// Abaqus hexahedron corners 1..8 -> deal.II's lexicographic vertex numbers.
constexpr unsigned int abaqus_to_deal[8] = {0, 1, 3, 2, 4, 5, 7, 6};
// Abaqus mid-side nodes 9..20 lie on these corner pairs (Abaqus numbering, 0-based).
constexpr unsigned int abaqus_edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                              {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

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
  double smallest = std::numeric_limits<double>::max(), largest = 0;
  for (const auto &grad : gradients)
    {
      Tensor<2, 3> J;
      for (unsigned int i = 0; i < 20; ++i) J += outer_product(x[i], grad[i]);
      smallest = std::min(smallest, determinant(J));
      largest = std::max(largest, std::abs(determinant(J)));
    }
  // A collapsed element (flattened to a face, an edge or a point) has a determinant that is
  // small everywhere, so the ratio above does not see it: its determinant is compared with that
  // of a cube of its longest edge h, (h / 2)^3 on the reference cell [-1, 1]^3.
  double longest_edge = 0;
  for (unsigned int l = 0; l < 12; ++l)
    longest_edge = std::max(longest_edge, x[GeometryInfo<3>::line_to_cell_vertices(l, 0)].distance(
                                            x[GeometryInfo<3>::line_to_cell_vertices(l, 1)]));
  const double cube = std::pow(longest_edge / 2, 3);
  if (smallest > 1e-10 * largest && !(smallest > 1e-9 * cube))
    {
      std::ostringstream m;
      m << label << (label.find(source) == std::string::npos ? " of '" + source + "'" : std::string())
        << " is collapsed: its Jacobian determinant is " << std::setprecision(3) << smallest / cube
        << " of that of a cube of its longest edge (" << longest_edge << " m; at least 1e-9 needed): check its node "
        << "coordinates";
      throw InputError(entry, m.str());
    }
  if (!(smallest > 1e-10 * largest))
    {
      std::ostringstream m;
      m << label << (label.find(source) == std::string::npos ? " of '" + source + "'" : std::string())
        << " is inverted or degenerate: its Jacobian determinant "
        << "reaches " << smallest << " (must stay > 0); check its node order (Abaqus: corners 1-4 "
        << "counter-clockwise, 5-8 above them) and its mid-side node positions";
      throw InputError(entry, m.str());
    }
}

/// Refuses two elements on the same corner nodes: they would fill the same space twice.
void refuse_coincident_elements(const MeshText &text, const RawMesh &raw)
{
  std::map<std::array<long, 8>, const RawElement *> seen;
  for (const auto &e : raw.elements)
    {
      std::array<long, 8> corners;
      std::copy(e.nodes.begin(), e.nodes.begin() + 8, corners.begin());
      std::sort(corners.begin(), corners.end());
      if (const auto [it, added] = seen.emplace(corners, &e); !added)
        text.fail_at(e.line, "element " + std::to_string(e.id) + " has the corner nodes of element " +
                                 std::to_string(it->second->id) + " (line " + std::to_string(it->second->line) +
                                 "); two elements may not fill the same space");
    }
}

/// Refuses inverted or degenerate cells, naming them, before deal.II sees the mesh.
void check_elements(const std::vector<Point<3>> &vertices, const std::vector<CellData<3>> &cells,
                    const SolidMesh &mesh, const std::string &entry)
{
  for (std::size_t c = 0; c < cells.size(); ++c)
    {
      std::array<Point<3>, 20> x;
      for (unsigned int v = 0; v < 8; ++v) x[v] = vertices[cells[c].vertices[v]];
      for (unsigned int l = 0; l < 12; ++l)
        {
          const unsigned int a = cells[c].vertices[GeometryInfo<3>::line_to_cell_vertices(l, 0)];
          const unsigned int b = cells[c].vertices[GeometryInfo<3>::line_to_cell_vertices(l, 1)];
          const auto it = mesh.midside.find(ordered_edge(a, b));
          x[8 + l] = it != mesh.midside.end() ? it->second : 0.5 * (vertices[a] + vertices[b]);
        }
      check_element(x, mesh.element_labels[c], mesh.source, entry);
    }
}

/// Node sets by mesh node; refuses members that name no defined node.
void add_node_sets(const MeshText &text, const RawMesh &raw, const std::map<long, MeshNode> &node_ref, SolidMesh &mesh)
{
  for (const auto &[name, members] : raw.sets)
    {
      auto &set = mesh.node_sets[name];
      for (const auto &member : members)
        if (const auto it = node_ref.find(member.node); it != node_ref.end())
          set.push_back(it->second);
        else if (!raw.nodes.count(member.node))
          text.fail_at(member.line, "node set '" + base::printable_excerpt(name) + "' names node " +
                                        std::to_string(member.node) + ", which is not defined under " +
                                        raw.node_section);
    }
}
} // namespace

/// Build the mesh from elements given with Abaqus node order (8 corners, then 12 mid-sides or
/// none), node coordinates and node sets by node id.
std::unique_ptr<SolidMesh> build_mesh(const MeshText &text, const RawMesh &raw)
{
  const std::string &file = text.file, &entry = text.entry;
  refuse_coincident_elements(text, raw);
  auto mesh = std::make_unique<SolidMesh>();
  mesh->source = file;
  auto position = [&](const RawElement &e, const long id) {
    const auto it = raw.nodes.find(id);
    if (it == raw.nodes.end())
      throw InputError(entry, "element " + std::to_string(e.id) + " at " + text.where(e.line) + " uses node " +
                              std::to_string(id) + ", which is not defined under " + raw.node_section);
    return it->second.first;
  };
  // Vertices: the corner nodes used by elements, numbered in order of first use.
  std::map<long, unsigned int> vertex_of;
  std::vector<Point<3>> vertices;
  for (const auto &e : raw.elements)
    for (unsigned int k = 0; k < 8; ++k)
      {
        const Point<3> x = position(e, e.nodes[k]);
        if (vertex_of.emplace(e.nodes[k], vertices.size()).second) vertices.push_back(x);
      }
  std::vector<CellData<3>> cells(raw.elements.size());
  std::map<long, MeshNode> node_ref; // file node id -> mesh node
  for (const auto &[id, v] : vertex_of) node_ref[id] = MeshNode{true, v, {0, 0}};
  for (std::size_t c = 0; c < raw.elements.size(); ++c)
    {
      const auto &e = raw.elements[c];
      for (unsigned int k = 0; k < 8; ++k) cells[c].vertices[abaqus_to_deal[k]] = vertex_of[e.nodes[k]];
      for (unsigned int k = 0; k < 12; ++k)
        {
          const unsigned int a = vertex_of[e.nodes[abaqus_edges[k][0]]], b = vertex_of[e.nodes[abaqus_edges[k][1]]];
          const auto key = ordered_edge(a, b);
          if (e.nodes.size() == 20)
            {
              const long mid = e.nodes[8 + k];
              mesh->midside[key] = position(e, mid);
              node_ref[mid] = MeshNode{false, 0, key};
            }
        }
      mesh->element_labels.push_back("element " + std::to_string(e.id) + " (" + text.where(e.line) + ")");
    }
  add_node_sets(text, raw, node_ref, *mesh);
  check_elements(vertices, cells, *mesh, entry);
  mesh->triangulation.create_triangulation(vertices, cells, SubCellData());
  return mesh;
}
} // namespace mesh_reading

std::unique_ptr<SolidMesh> read_mesh_file(const std::string &file, const std::string &entry)
{
  mesh_reading::check_mesh_file(file, entry, "Abaqus/CalculiX .inp or Gmsh .msh file");
  const std::string extension = mesh_reading::upper(std::filesystem::path(file).extension().string());
  if (extension == ".INP") return read_abaqus_mesh(file, entry);
  if (extension == ".MSH") return read_gmsh_mesh(file, entry);
  throw InputError(entry, "cannot tell the format of '" + file + "' from its extension; allowed: .inp "
                   "(Abaqus/CalculiX) and .msh (Gmsh 2.2 or 4.1, ASCII)");
}
} // namespace flextrack::fem
