// Private to src/fem: what the mesh file readers (abaqus_mesh_reader.cc, gmsh_mesh_reader.cc)
// share with solid_mesh.cc. A reader turns the text of a file into a RawMesh (nodes, hexahedra in
// Abaqus node order, node sets, each with the line it came from); build_mesh() turns that into a
// SolidMesh. Everything a file can get wrong is refused here with an InputError naming the file,
// the line, what is wrong and what is allowed, before anything is allocated from a count in it.
#pragma once

#include <fem/solid_mesh.h>

#include <deal.II/base/point.h>

#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::fem::mesh_reading
{
/// Mesh files are refused beyond this size (1 GiB): far more than the solver handles, and the
/// bound on what a reader may ever read (an endless device file cannot run forever).
constexpr std::uintmax_t max_file_size = std::uintmax_t(1) << 30;
/// No coordinate may exceed this magnitude [m]: beyond it, Jacobians and stiffness overflow.
constexpr double max_coordinate = 1e9;

/// Refuses, naming @p file and saying what it is, a mesh file that does not exist, is a
/// directory, a device, a pipe or a socket, or is larger than max_file_size. @p kind says what
/// is expected ("an Abaqus/CalculiX .inp file").
void check_mesh_file(const std::string &file, const std::string &entry, const std::string &kind);

/// The text of a mesh file, line by line. Refuses a file that is not text (UTF-16, binary:
/// a short printable excerpt is quoted, never the raw bytes) and lines beyond 1 MiB. Parses the
/// words of a line with messages naming the file and the line.
class MeshText
{
public:
  MeshText(const std::string &file, const std::string &entry, const std::string &kind);

  /// The next line, without its line end; false at the end of the file.
  bool next(std::string &line);
  /// The next line; InputError "ends early" at the end of the file.
  std::string next_or_fail();
  int line_number() const { return number; }
  /// "FILE, line N".
  std::string where(int line) const;

  /// InputError "cannot read FILE, line N: what" (N: the current line, or @p line).
  [[noreturn]] void fail(const std::string &what) const;
  [[noreturn]] void fail_at(int line, const std::string &what) const;

  /// The whole of @p word as an integer; else fail(), saying it is not @p what.
  long integer(const std::string &word, const std::string &what) const;
  /// A coordinate: finite and at most max_coordinate in magnitude; else fail() naming @p node.
  double coordinate(const std::string &word, long node) const;
  /// A count of items of at least @p bytes_per_item bytes each: from 0 to what the rest of the
  /// file can hold; else fail(), saying what a count of @p what allows.
  long count(const std::string &word, const std::string &what, std::uintmax_t bytes_per_item) const;

  const std::string file, entry;

private:
  std::ifstream in;
  std::uintmax_t size = 0, bytes_read = 0;
  int number = 0;
};

/// A hexahedron as read: 8 corners, then 12 mid-side nodes or none, in Abaqus order.
struct RawElement
{
  long id;
  int line;
  std::vector<long> nodes;
};

/// A member of a node set and the line that names it.
struct SetMember
{
  long node;
  int line;
};

/// What a reader found in a file.
struct RawMesh
{
  /// Where nodes are defined ("*NODE", "$Nodes"), for messages.
  std::string node_section;
  std::map<long, std::pair<dealii::Point<3>, int>> nodes; ///< id -> (position, line)
  std::vector<RawElement> elements;
  std::map<long, int> element_lines; ///< id -> line, to refuse a repeated id
  std::map<std::string, std::vector<SetMember>> sets;
  std::size_t n_set_members = 0; ///< members of all sets, counted by count_set_members()

  /// Counts @p more members about to be added to the sets; refuses (at @p line) more than
  /// max(1e7, 64 per node) in all. GENERATE ranges and physical tags could otherwise multiply a
  /// small file into any amount of memory.
  void count_set_members(const MeshText &text, int line, std::size_t more);

  /// Adds node @p id at the current line of @p text; refuses an id given before (naming both lines).
  void add_node(const MeshText &text, long id, const dealii::Point<3> &position);
  /// Adds @p element; refuses an id given before (naming both lines).
  void add_element(const MeshText &text, RawElement &&element);
};

/// The mesh of @p raw. Refuses elements and set members that name undefined nodes, and inverted
/// or degenerate elements.
std::unique_ptr<SolidMesh> build_mesh(const MeshText &text, const RawMesh &raw);

/// @p s in upper case (ASCII).
std::string upper(std::string s);
} // namespace flextrack::fem::mesh_reading
