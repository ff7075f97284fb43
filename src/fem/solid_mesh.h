// A hexahedral mesh of a 3D body with the geometry of 20-node elements: the corner nodes make a
// deal.II Triangulation<3>, and every edge keeps its mid-side node position, so curved edges
// are reproduced isoparametrically. Named node sets (Abaqus *NSET, or generated faces) refer
// to corner nodes and mid-side nodes alike.
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace flextrack::fem
{
/// A node of the 20-node geometry: a triangulation vertex, or the midpoint of the edge between
/// two vertices (stored with the smaller vertex index first).
struct MeshNode
{
  bool is_vertex = true;
  unsigned int vertex = 0;
  std::pair<unsigned int, unsigned int> edge{0, 0};
  bool operator<(const MeshNode &o) const
  {
    return std::tie(is_vertex, vertex, edge) < std::tie(o.is_vertex, o.vertex, o.edge);
  }
};

/// The edge between two vertices as (smaller index, larger index), by value.
inline std::pair<unsigned int, unsigned int> ordered_edge(const unsigned int a, const unsigned int b)
{
  return a < b ? std::make_pair(a, b) : std::make_pair(b, a);
}

struct SolidMesh
{
  std::string source;                                  ///< file name, or a description
  dealii::Triangulation<3> triangulation;
  std::map<std::pair<unsigned int, unsigned int>, dealii::Point<3>> midside; ///< edge -> position
  std::map<std::string, std::vector<MeshNode>> node_sets;
  std::vector<std::string> element_labels;             ///< per coarse cell: "element 17 (line 40)"

  /// Position of a node of the 20-node geometry.
  dealii::Point<3> position(const MeshNode &node) const;
  /// Mid-side position of a cell's line: stored, else the straight midpoint.
  dealii::Point<3> line_midpoint(unsigned int v0, unsigned int v1) const;
};

/// Read an Abaqus / CalculiX input file: *NODE, *ELEMENT (TYPE = C3D8, C3D8R, C3D8I, C3D20,
/// C3D20R), *NSET (with or without GENERATE). Other keywords are skipped. Elements of any other
/// type are refused, naming the type, the file and the line; so are inverted or degenerate
/// elements (Jacobian determinant <= 0 at a 3x3x3 Gauss point). Throws InputError.
std::unique_ptr<SolidMesh> read_abaqus_mesh(const std::string &file, const std::string &entry);

/// Read a Gmsh mesh (MSH 2.2 or 4.1, ASCII): 8-node (type 5) and 20-node (type 17) hexahedra;
/// physical groups of points, curves and surfaces become node sets named after the group
/// (upper case). Other volume elements are refused, naming the type, the file and the line.
std::unique_ptr<SolidMesh> read_gmsh_mesh(const std::string &file, const std::string &entry);

/// .inp or .msh, by extension.
///
/// Both readers refuse, with one line naming the file, the line and what is allowed: a path that
/// is not a regular file (a directory, a device such as /dev/zero), a file over 1 GiB, a file
/// that is not text (binary, UTF-16: only a short printable excerpt is quoted), lines over
/// 1 MiB, counts beyond what the rest of the file can hold, repeated node or element numbers,
/// two elements on the same corner nodes, node sets naming undefined nodes, *NSET, GENERATE
/// ranges that are empty, endless or longer than the node count, node sets of more than
/// max(1e7, 64 per node) members in all, and coordinates that are not finite or exceed 1e9 m.
std::unique_ptr<SolidMesh> read_mesh_file(const std::string &file, const std::string &entry);

/// A box [0, Lx] x [0, Ly] x [0, Lz] with nx x ny x nz cells; node sets "xmin", "xmax", "ymin",
/// "ymax", "zmin", "zmax" hold the nodes of its faces.
std::unique_ptr<SolidMesh> generate_box(const dealii::Point<3> &size, const std::array<unsigned int, 3> &cells);

/// A solid circular cylinder of radius R along x from 0 to L (deal.II's subdivided_cylinder:
/// 5 cells per cross-section, n_axial along the axis), its hull edges curved (mid-side nodes on
/// the circle); node sets HULL, XMIN (x = 0), XMAX (x = L).
std::unique_ptr<SolidMesh> generate_cylinder(double radius, double length, unsigned int n_axial);
} // namespace flextrack::fem
