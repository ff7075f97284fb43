// The Gmsh .msh reader (MSH 2.2 and 4.1, ASCII): one function per section ($MeshFormat,
// $PhysicalNames, $Entities, $Nodes, $Elements), per version where the versions differ. Every
// count in the file is checked against what the rest of the file can hold before it is used.
#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>
#include <fem/raw_mesh.h>
#include <fem/solid_mesh.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>

namespace flextrack::fem
{
using dealii::Point;
using mesh_reading::MeshText;
using mesh_reading::RawElement;
using mesh_reading::RawMesh;
using mesh_reading::SetMember;
using mesh_reading::upper;

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
int gmsh_nodes_per_element(const long type)
{
  static const std::map<long, int> n = {{1, 2}, {2, 3}, {3, 4}, {4, 4}, {5, 8}, {6, 6}, {7, 5}, {8, 3}, {9, 6},
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

/// The blank-separated words of a line.
std::vector<std::string> words(const std::string &line)
{
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

/// Reads a .msh file section by section into a RawMesh.
class GmshReader
{
public:
  GmshReader(const std::string &file, const std::string &entry) : text(file, entry, "Gmsh .msh file")
  {
    raw.node_section = "$Nodes";
  }
  std::unique_ptr<SolidMesh> read();

private:
  void mesh_format();
  void physical_names();
  void entities();
  void nodes_v2();
  void nodes_v4();
  void elements_v2();
  void elements_v4();
  /// The words of the next line, at least @p n of them; else fail() saying the line's @p form.
  std::vector<std::string> next_words(std::size_t n, const std::string &form);
  /// The node numbers of element @p id of type @p type: @p per words of @p w from @p first.
  std::vector<long> element_nodes(const std::vector<std::string> &w, std::size_t first, long id, int per) const;
  /// A hexahedron (Gmsh order) to the elements; other volume elements are refused.
  void add_volume_element(long id, int type, const std::vector<long> &gmsh_nodes);
  void add_to_sets(const std::vector<long> &physicals, long dim, const std::vector<long> &element_nodes);

  MeshText text;
  RawMesh raw;
  double version = 0;
  std::map<std::pair<long, long>, std::string> names;                 // (dim, tag) -> physical name
  std::map<std::pair<long, long>, std::vector<long>> entity_physicals; // v4: (dim, entity) -> physical tags
};

std::unique_ptr<SolidMesh> GmshReader::read()
{
  for (std::string line; text.next(line);)
    {
      const std::string section = base::trim(line);
      if (section == "$MeshFormat") mesh_format();
      else if (section == "$PhysicalNames") physical_names();
      else if (section == "$Entities") entities();
      else if (section == "$Nodes") version < 3 ? nodes_v2() : nodes_v4();
      else if (section == "$Elements") version < 3 ? elements_v2() : elements_v4();
    }
  if (version == 0)
    throw InputError(text.entry, "'" + text.file + "' is not a Gmsh mesh (no $MeshFormat section)");
  if (raw.elements.empty())
    throw InputError(text.entry, "'" + text.file + "' holds no hexahedra (Gmsh element types 5 or 17)");
  for (auto &[name, members] : raw.sets)
    {
      std::sort(members.begin(), members.end(), [](const SetMember &a, const SetMember &b) {
        return std::tie(a.node, a.line) < std::tie(b.node, b.line);
      });
      members.erase(std::unique(members.begin(), members.end(),
                                [](const SetMember &a, const SetMember &b) { return a.node == b.node; }),
                    members.end());
    }
  return build_mesh(text, raw);
}

std::vector<std::string> GmshReader::next_words(const std::size_t n, const std::string &form)
{
  auto w = words(text.next_or_fail());
  if (w.size() < n) text.fail("the line must be '" + form + "'");
  return w;
}

void GmshReader::mesh_format()
{
  const auto w = next_words(1, "version file-type data-size");
  char *end = nullptr;
  version = std::strtod(w[0].c_str(), &end);
  if (end != w[0].c_str() + w[0].size()) version = -1;
  if (w.size() > 1 && w[1] != "0") text.fail("binary .msh files are not supported; save the mesh as ASCII");
  if (!(version >= 2 && version < 3) && !(version >= 4.1 && version < 5))
    text.fail("MSH format version '" + base::printable_excerpt(w[0], 20) +
              "' is not supported; allowed: 2.2 and 4.1 (ASCII)");
}

void GmshReader::physical_names()
{
  const long n = text.count(next_words(1, "number-of-names")[0], "physical names", 6);
  for (long i = 0; i < n; ++i)
    {
      std::istringstream f(text.next_or_fail());
      std::string dim, tag, name;
      f >> dim >> tag;
      std::getline(f, name);
      name = base::trim(name);
      if (name.size() >= 2 && name.front() == '"') name = name.substr(1, name.size() - 2);
      names[{text.integer(dim, "a dimension"), text.integer(tag, "a physical tag")}] = name;
    }
}

void GmshReader::entities()
{
  const auto w = next_words(4, "points curves surfaces volumes");
  long count[4];
  for (int dim = 0; dim < 4; ++dim) count[dim] = text.count(w[dim], "entities of dimension " + std::to_string(dim), 10);
  for (long dim = 0; dim < 4; ++dim)
    for (long i = 0; i < count[dim]; ++i)
      {
        const std::size_t n_box = dim == 0 ? 3 : 6; // a point's coordinates, else a bounding box
        const auto e = next_words(n_box + 2, dim == 0 ? "tag x y z physical-tags..." : "tag box(6) physical-tags...");
        const long tag = text.integer(e[0], "an entity tag");
        const long n_physical = text.integer(e[n_box + 1], "a count of physical tags");
        const std::size_t room = e.size() - (n_box + 2);
        if (n_physical < 0 || static_cast<std::size_t>(n_physical) > room)
          text.fail("entity " + std::to_string(tag) + " announces " + std::to_string(n_physical) +
                    " physical tags; its line holds " + std::to_string(room) + " more numbers (allowed: 0 to " +
                    std::to_string(room) + ")");
        auto &list = entity_physicals[{dim, tag}];
        for (long k = 0; k < n_physical; ++k)
          list.push_back(std::abs(text.integer(e[n_box + 2 + k], "a physical tag")));
      }
}

void GmshReader::nodes_v2()
{
  // A node line is at least "1 0 0 0\n": 8 bytes.
  const long n = text.count(next_words(1, "number-of-nodes")[0], "nodes", 8);
  for (long i = 0; i < n; ++i)
    {
      const auto w = words(text.next_or_fail());
      if (w.size() < 4) text.fail("a node line must be 'id x y z'");
      const long id = text.integer(w[0], "a node number");
      raw.add_node(text, id, Point<3>(text.coordinate(w[1], id), text.coordinate(w[2], id), text.coordinate(w[3], id)));
    }
}

void GmshReader::nodes_v4()
{
  // A node takes a tag line and a coordinate line, at least "1\n" and "0 0 0\n": 8 bytes.
  const auto header = next_words(4, "blocks nodes min-tag max-tag");
  const long blocks = text.count(header[0], "node blocks", 8);
  text.count(header[1], "nodes", 8);
  for (long b = 0; b < blocks; ++b)
    {
      const auto w = next_words(4, "entity-dim entity-tag parametric nodes-in-block");
      const long count = text.count(w[3], "nodes in a block", 8);
      std::vector<long> ids(count);
      for (auto &id : ids)
        {
          const auto t = words(text.next_or_fail());
          if (t.size() != 1) text.fail("a node tag line holds one node number");
          id = text.integer(t[0], "a node number");
        }
      for (const long id : ids)
        {
          const auto x = words(text.next_or_fail());
          if (x.size() < 3) text.fail("a node line must be 'x y z'");
          raw.add_node(text, id,
                       Point<3>(text.coordinate(x[0], id), text.coordinate(x[1], id), text.coordinate(x[2], id)));
        }
    }
}

std::vector<long> GmshReader::element_nodes(const std::vector<std::string> &w, const std::size_t first, const long id,
                                            const int per) const
{
  if (w.size() < first + per) text.fail("element " + std::to_string(id) + " has too few nodes");
  std::vector<long> nodes(per);
  for (int k = 0; k < per; ++k) nodes[k] = text.integer(w[first + k], "a node number");
  return nodes;
}

void GmshReader::elements_v2()
{
  // An element line is at least "1 15 0 1\n": 8 bytes and more.
  const long n = text.count(next_words(1, "number-of-elements")[0], "elements", 8);
  for (long i = 0; i < n; ++i)
    {
      const auto w = next_words(3, "id type number-of-tags tags... nodes...");
      const long id = text.integer(w[0], "an element number");
      const long type = text.integer(w[1], "an element type");
      const long n_tags = text.integer(w[2], "a count of tags");
      const std::size_t room = w.size() - 3;
      if (n_tags < 0 || static_cast<std::size_t>(n_tags) > room)
        text.fail("element " + std::to_string(id) + " announces " + std::to_string(n_tags) + " tags; its line holds " +
                  std::to_string(room) + " more numbers (allowed: 0 to " + std::to_string(room) + ")");
      const long physical = n_tags > 0 ? text.integer(w[3], "a physical tag") : 0;
      const int per = gmsh_nodes_per_element(type);
      if (per == 0) text.fail("unknown element type " + std::to_string(type));
      const auto nodes = element_nodes(w, 3 + n_tags, id, per);
      if (gmsh_is_volume(type))
        add_volume_element(id, type, nodes);
      else if (physical != 0)
        {
          raw.count_set_members(text, text.line_number(), nodes.size());
          add_to_sets({physical}, type == 15 ? 0 : (type == 1 || type == 8) ? 1 : 2, nodes);
        }
    }
}

void GmshReader::elements_v4()
{
  const auto header = next_words(4, "blocks elements min-tag max-tag");
  const long blocks = text.count(header[0], "element blocks", 8);
  text.count(header[1], "elements", 4);
  for (long b = 0; b < blocks; ++b)
    {
      const auto w = next_words(4, "entity-dim entity-tag element-type elements-in-block");
      const long dim = text.integer(w[0], "a dimension"), tag = text.integer(w[1], "an entity tag");
      const long type = text.integer(w[2], "an element type");
      const int per = gmsh_nodes_per_element(type);
      if (per == 0) text.fail("unknown element type " + std::to_string(type));
      // An element line holds its number and its nodes, each at least one digit and a blank.
      const long count = text.count(w[3], "elements in a block", 2 * (per + 1));
      // Each element adds its nodes to each physical group of the entity: counted before.
      const auto physicals = dim == 3 ? entity_physicals.end() : entity_physicals.find({dim, tag});
      if (physicals != entity_physicals.end())
        raw.count_set_members(text, text.line_number(), count * per * physicals->second.size());
      for (long i = 0; i < count; ++i)
        {
          const auto e = next_words(1, "id nodes...");
          const long id = text.integer(e[0], "an element number");
          const auto nodes = element_nodes(e, 1, id, per);
          if (dim == 3)
            add_volume_element(id, type, nodes);
          else if (physicals != entity_physicals.end())
            add_to_sets(physicals->second, dim, nodes);
        }
    }
}

void GmshReader::add_volume_element(const long id, const int type, const std::vector<long> &gmsh_nodes)
{
  if (type != 5 && type != 17)
    throw InputError(text.entry, "unsupported element: " + gmsh_type_name(type) + " (element " + std::to_string(id) +
                                     ") at " + text.where(text.line_number()) +
                                     "; allowed volume elements: 8-node and 20-node hexahedra (Gmsh types 5 and 17)");
  RawElement e{id, text.line_number(), std::vector<long>(gmsh_nodes.begin(), gmsh_nodes.begin() + 8)};
  if (type == 17)
    {
      e.nodes.resize(20);
      for (unsigned int m = 0; m < 12; ++m) e.nodes[8 + gmsh_to_abaqus_midside[m]] = gmsh_nodes[8 + m];
    }
  raw.add_element(text, std::move(e));
}

void GmshReader::add_to_sets(const std::vector<long> &physicals, const long dim, const std::vector<long> &element_nodes)
{
  for (const long tag : physicals)
    {
      const auto it = names.find({dim, tag});
      auto &set = raw.sets[it != names.end() ? upper(it->second) : "PHYSICAL_" + std::to_string(tag)];
      for (const long node : element_nodes) set.push_back({node, text.line_number()});
    }
}
} // namespace

std::unique_ptr<SolidMesh> read_gmsh_mesh(const std::string &file, const std::string &entry)
{
  return GmshReader(file, entry).read();
}
} // namespace flextrack::fem
