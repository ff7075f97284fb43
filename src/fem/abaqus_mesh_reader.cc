// The Abaqus / CalculiX .inp reader: *NODE, *ELEMENT (hexahedra), *NSET (with or without
// GENERATE); every other keyword and its data lines are skipped.
#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>
#include <fem/raw_mesh.h>
#include <fem/solid_mesh.h>

#include <algorithm>
#include <limits>
#include <sstream>

namespace flextrack::fem
{
using dealii::Point;
using mesh_reading::MeshText;
using mesh_reading::RawElement;
using mesh_reading::RawMesh;
using mesh_reading::upper;

namespace
{
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

/// The comma-separated fields of a data line, trimmed (empty ones kept).
std::vector<std::string> fields(const std::string &line)
{
  std::vector<std::string> f;
  std::istringstream in(line);
  for (std::string item; std::getline(in, item, ',');) f.push_back(trim(item));
  return f;
}

/// The integers of a data line; empty items are skipped (a line may end with a comma).
std::vector<long> integers(const MeshText &text, const std::string &line, const std::string &what)
{
  std::vector<long> v;
  for (const auto &item : fields(line))
    if (!item.empty()) v.push_back(text.integer(item, what));
  return v;
}

/// A *NSET, GENERATE line "first, last, increment", expanded once the number of nodes is known.
struct GenerateRange
{
  std::string set;
  long first, last, step;
  int line;
};

/// Reads an .inp file line by line into a RawMesh, one function per kind of line.
class AbaqusReader
{
public:
  AbaqusReader(const std::string &file, const std::string &entry) : text(file, entry, "Abaqus/CalculiX .inp file")
  {
    raw.node_section = "*NODE";
  }
  std::unique_ptr<SolidMesh> read();

private:
  void keyword(const std::string &line);
  void node_line(const std::string &line);
  void element_line(const std::string &line);
  void nset_line(const std::string &line);
  void add_generated_members();

  MeshText text;
  RawMesh raw;
  enum class Block { none, node, element, nset } block = Block::none;
  bool generate = false;
  std::string set_name;
  int nodes_per_element = 0;
  std::vector<long> pending; // an element's node list may continue on the next line
  int pending_line = 0;
  std::vector<GenerateRange> ranges;
};

std::unique_ptr<SolidMesh> AbaqusReader::read()
{
  for (std::string line; text.next(line);)
    {
      const std::string t = trim(line);
      if (t.empty() || t.rfind("**", 0) == 0) continue;
      if (t[0] == '*') keyword(t);
      else if (block == Block::node) node_line(t);
      else if (block == Block::element) element_line(t);
      else if (block == Block::nset) nset_line(t);
    }
  if (!pending.empty())
    throw InputError(text.entry, "the element at " + text.where(pending_line) + " has too few nodes");
  if (raw.elements.empty())
    throw InputError(text.entry, "'" + text.file + "' holds no hexahedral elements (*ELEMENT, TYPE=C3D8 or C3D20)");
  add_generated_members();
  return build_mesh(text, raw);
}

void AbaqusReader::keyword(const std::string &t)
{
  if (!pending.empty())
    throw InputError(text.entry, "the element at " + text.where(pending_line) + " has too few nodes");
  const auto comma = t.find(',');
  const std::string key = upper(trim(t.substr(1, comma == std::string::npos ? std::string::npos : comma - 1)));
  block = Block::none;
  if (key == "NODE")
    block = Block::node;
  else if (key == "ELEMENT")
    {
      const std::string type = upper(option(t, "TYPE"));
      if (type == "C3D8" || type == "C3D8R" || type == "C3D8I")
        nodes_per_element = 8;
      else if (type == "C3D20" || type == "C3D20R")
        nodes_per_element = 20;
      else
        throw InputError(text.entry, "unsupported element type '" + base::printable_excerpt(type, 30) + "' at " +
                                         text.where(text.line_number()) +
                                         "; allowed: hexahedra C3D8, C3D8R, C3D8I, C3D20, C3D20R (tetrahedra, "
                                         "wedges, shells and beams cannot be read)");
      block = Block::element;
    }
  else if (key == "NSET")
    {
      set_name = upper(option(t, "NSET"));
      generate = upper(t).find("GENERATE") != std::string::npos;
      block = Block::nset;
    }
}

void AbaqusReader::node_line(const std::string &t)
{
  const auto f = fields(t);
  if (f.size() < 3 || f[0].empty())
    throw InputError(text.entry, "a node line must be 'id, x, y, z' at " + text.where(text.line_number()));
  const long id = text.integer(f[0], "a node number");
  const double z = f.size() < 4 || f[3].empty() ? 0.0 : text.coordinate(f[3], id);
  raw.add_node(text, id, Point<3>(text.coordinate(f[1], id), text.coordinate(f[2], id), z));
}

void AbaqusReader::element_line(const std::string &t)
{
  const auto v = integers(text, t, "an element or node number");
  if (pending.empty()) pending_line = text.line_number();
  pending.insert(pending.end(), v.begin(), v.end());
  if (static_cast<int>(pending.size()) >= nodes_per_element + 1)
    {
      if (static_cast<int>(pending.size()) > nodes_per_element + 1)
        throw InputError(text.entry, "element with more than " + std::to_string(nodes_per_element) + " nodes at " +
                                         text.where(pending_line));
      RawElement element{pending[0], pending_line, std::vector<long>(pending.begin() + 1, pending.end())};
      raw.add_element(text, std::move(element));
      pending.clear();
    }
}

void AbaqusReader::nset_line(const std::string &t)
{
  const auto v = integers(text, t, "a node number");
  auto &set = raw.sets[set_name];
  if (!generate)
    {
      for (const long id : v) set.push_back({id, text.line_number()});
      return;
    }
  if (v.size() != 2 && v.size() != 3)
    text.fail("a *NSET, GENERATE line is 'first, last' or 'first, last, increment'");
  const long step = v.size() == 3 ? v[2] : 1;
  if (!(v[0] <= v[1] && step >= 1))
    text.fail("*NSET, GENERATE from " + std::to_string(v[0]) + " to " + std::to_string(v[1]) + " by " +
              std::to_string(step) + ": allowed are first <= last and an increment >= 1");
  ranges.push_back({set_name, v[0], v[1], step, text.line_number()});
}

/// The members of the GENERATE ranges, once the nodes are known: a range may not imply more
/// members than the file has nodes, nor all of them more than RawMesh::count_set_members()
/// allows (checked before anything is allocated).
void AbaqusReader::add_generated_members()
{
  for (const auto &r : ranges)
    {
      // last - first in unsigned arithmetic cannot overflow, as first <= last.
      const unsigned long n_minus_one = (static_cast<unsigned long>(r.last) - static_cast<unsigned long>(r.first)) /
                                        static_cast<unsigned long>(r.step);
      if (n_minus_one >= raw.nodes.size())
        {
          const bool all = n_minus_one == std::numeric_limits<unsigned long>::max(); // 2^64 members
          text.fail_at(r.line, "*NSET, GENERATE from " + std::to_string(r.first) + " to " + std::to_string(r.last) +
                                   " by " + std::to_string(r.step) + " names " +
                                   (all ? std::string("2^64") : std::to_string(n_minus_one + 1)) +
                                   " nodes, more than the " + std::to_string(raw.nodes.size()) + " the file defines");
        }
      raw.count_set_members(text, r.line, n_minus_one + 1);
      auto &set = raw.sets[r.set];
      for (unsigned long k = 0; k <= n_minus_one; ++k)
        set.push_back({static_cast<long>(static_cast<unsigned long>(r.first) + k * r.step), r.line});
    }
  // In the order of the file, as if each range had been expanded where it stands.
  if (!ranges.empty())
    for (auto &[name, members] : raw.sets)
      std::stable_sort(members.begin(), members.end(), [](const auto &a, const auto &b) { return a.line < b.line; });
}
} // namespace

std::unique_ptr<SolidMesh> read_abaqus_mesh(const std::string &file, const std::string &entry)
{
  return AbaqusReader(file, entry).read();
}
} // namespace flextrack::fem
