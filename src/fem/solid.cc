#include <fem/solid.h>
#include <base/text.h>
#include <geometry/curve_library.h>

#include <unistd.h>

#include <cmath>
#include <base/input_error.h>

#include <sstream>

namespace flextrack::fem
{
using dealii::ParameterHandler;

namespace
{
/// Most cells of a generated mesh (box or cylinder): a bound on typos such as 2147483647.
constexpr double max_generated_cells = 1e6;
const geometry::NumberRange size_range{0, geometry::max_coordinate, false, "m"};

/// A lower bound of the memory a solid of @p cells cells needs [bytes]: its degrees of freedom
/// (3 per node; about 1, 4 and 8 nodes per cell of a large hex8, hex20 and hex27 mesh) times the
/// nonzeros of a stiffness row (about 81, 150, 200), for K, M and a factor at least as large, at
/// 12 bytes per nonzero. Fill-in makes the real need larger (measured: 30 x 30 x 30 hex20 cells,
/// 3.5e5 degrees of freedom, 9.5 GiB).
double solid_memory_lower_bound(const double cells, const SolidElement element, double &dofs)
{
  const double nodes_per_cell = element == SolidElement::hex8 ? 1 : element == SolidElement::hex20 ? 4 : 8;
  const double row = element == SolidElement::hex8 ? 81 : element == SolidElement::hex20 ? 150 : 200;
  dofs = 3 * nodes_per_cell * cells;
  return dofs * row * 12 * 3;
}

std::string gibibytes(const double bytes)
{
  std::ostringstream m;
  m.precision(3);
  m << bytes / (1024.0 * 1024 * 1024) << " GiB";
  return m.str();
}
} // namespace

void check_solid_cell_count(const double cells, const SolidElement element, const std::string &entry)
{
  double dofs = 0;
  const double bytes = solid_memory_lower_bound(cells, element, dofs);
  const double physical = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  std::ostringstream m;
  m.precision(3);
  m << cells << " cells (about " << dofs << " degrees of freedom) need at least " << gibibytes(bytes)
    << " of memory";
  if (cells > max_generated_cells)
    throw InputError(entry, m.str() + "; allowed: at most 1000000 cells in all");
  if (physical > 0 && bytes > physical)
    throw InputError(entry, m.str() + ", more than this computer's " + gibibytes(physical) + "; use fewer cells");
}

void Solid::declare_parameters(ParameterHandler &prm)
{
  prm.enter_subsection("Solid");
  prm.declare_entry("Mesh", "box", dealii::Patterns::Selection("box|cylinder|file"),
                    "Where the hexahedral mesh comes from: 'box' or 'cylinder' (generated, see the subsections of "
                    "those names) or 'file' (Mesh file).");
  prm.declare_entry("Mesh file", "", dealii::Patterns::FileName(dealii::Patterns::FileName::input),
                    "Mesh file, relative to the parameter file, coordinates in m: Abaqus/CalculiX .inp (C3D8 or "
                    "C3D20 hexahedra, *NSET node sets) or Gmsh .msh (2.2 or 4.1 ASCII; 8- or 20-node hexahedra; "
                    "physical groups become node sets).");
  prm.enter_subsection("Box");
  prm.declare_entry("Size", "1, 0.1, 0.1", dealii::Patterns::List(dealii::Patterns::Double(0), 3, 3, ","),
                    "Edge lengths Lx, Ly, Lz [m] of the box [0, Lx] x [0, Ly] x [0, Lz], each > 0 and <= 1e6. Its "
                    "node sets are XMIN, XMAX, YMIN, YMAX, ZMIN, ZMAX (the nodes of each face).");
  prm.declare_entry("Cells", "10, 1, 1", dealii::Patterns::List(dealii::Patterns::Integer(1), 3, 3, ","),
                    "Number of cells along x, y, z [-]; at most 1000000 in all, and no more than the memory of "
                    "the computer holds (estimated before meshing).");
  prm.leave_subsection();
  prm.enter_subsection("Cylinder");
  prm.declare_entry("Radius", "0.05", dealii::Patterns::Double(0), "Radius R of the solid cylinder [m], > 0 and <= 1e6.");
  prm.declare_entry("Length", "1", dealii::Patterns::Double(0),
                    "Length L [m], > 0 and <= 1e6: the axis runs along x from 0 to L. Node sets: HULL, XMIN, XMAX.");
  prm.declare_entry("Cells along the axis", "10", dealii::Patterns::Integer(1),
                    "Number of cells along the axis [-]; each cross-section has 5 cells; at most 200000 (1000000 "
                    "cells), and no more than the memory of the computer holds.");
  prm.leave_subsection();
  prm.declare_entry("Element", "hex20", dealii::Patterns::Selection("hex20|hex8|hex27"),
                    "Finite element: 'hex20' (20-node serendipity, seed eq. 30, as CalculiX C3D20), 'hex8' "
                    "(deal.II FE_Q(1)), 'hex27' (deal.II FE_Q(2)). The geometry is always the 20-node map.");
  prm.declare_entry("Integration", "full", dealii::Patterns::Selection("full|reduced"),
                    "Gauss rule per direction: 'full' = 3 points (hex8: 2), 'reduced' = 2 points (hex8: 1).");
  prm.declare_entry("Supports", "XMIN: x, y, z", dealii::Patterns::Anything(),
                    "Fixed displacement components, ';'-separated, each 'WHERE: components' with WHERE a node "
                    "set name or a plane 'x = 0.0' [m] (at most 1e6 m in size), and components from x, y, z; e.g. "
                    "'XMIN: x, y, z; y = 0: y'. Empty: a free body (six zero-frequency modes).");
  Material::declare_parameters(prm);
  prm.leave_subsection();
}

SolidSupport parse_support_place(const std::string &place, const std::string &entry)
{
  SolidSupport support;
  std::string where = base::trim(place);
  const auto eq = where.find('=');
  if (eq != std::string::npos)
    {
      const std::string axis = base::trim(where.substr(0, eq));
      if (axis != "x" && axis != "y" && axis != "z")
        throw InputError(entry, "'" + base::printable_excerpt(where) +
                                  "': a plane is 'x = value', 'y = value' or 'z = value' [m]");
      support.plane_axis = axis[0] - 'x';
      support.plane_position = geometry::checked_number(
        base::parse_number(where.substr(eq + 1), entry, "the plane position [m]"), entry,
        {-geometry::max_coordinate, geometry::max_coordinate, true, "m"});
    }
  else
    {
      for (auto &c : where) c = std::toupper(static_cast<unsigned char>(c));
      support.node_set = where;
    }
  return support;
}

bool same_place(const SolidSupport &a, const SolidSupport &b)
{
  if (a.plane_axis < 0 || b.plane_axis < 0) return a.plane_axis == b.plane_axis && a.node_set == b.node_set;
  return a.plane_axis == b.plane_axis &&
         std::abs(a.plane_position - b.plane_position) <= 1e-12 * std::max(1.0, std::abs(a.plane_position));
}

Solid Solid::parse_parameters(ParameterHandler &prm, const std::string &directory)
{
  Solid s;
  prm.enter_subsection("Solid");
  const std::string entry = "Solid/Supports";
  // The element first: the memory estimate of a generated mesh depends on it.
  const std::string element = prm.get("Element");
  s.element = element == "hex8" ? SolidElement::hex8 : element == "hex27" ? SolidElement::hex27 : SolidElement::hex20;
  if (prm.get("Mesh") == "file")
    {
      std::string file = prm.get("Mesh file");
      if (!file.empty() && file[0] != '/') file = directory + "/" + file;
      s.mesh = read_mesh_file(file, "Solid/Mesh file");
    }
  else if (prm.get("Mesh") == "cylinder")
    {
      prm.enter_subsection("Cylinder");
      const double R = geometry::get_number(prm, "Radius", "Solid/Cylinder/", size_range);
      const double L = geometry::get_number(prm, "Length", "Solid/Cylinder/", size_range);
      const long n = prm.get_integer("Cells along the axis");
      prm.leave_subsection();
      check_solid_cell_count(5.0 * n, s.element, "Solid/Cylinder/Cells along the axis");
      s.mesh = generate_cylinder(R, L, n);
    }
  else
    {
      prm.enter_subsection("Box");
      const std::array<double, 3> size = base::parse_vector3(prm.get("Size"), "Solid/Box/Size", "m");
      const auto cell_counts = base::parse_vector3(prm.get("Cells"), "Solid/Box/Cells", "-");
      prm.leave_subsection();
      for (int d = 0; d < 3; ++d)
        {
          geometry::checked_number(size[d], "Solid/Box/Size", size_range);
          if (!(cell_counts[d] >= 1 && cell_counts[d] == std::floor(cell_counts[d])))
            throw InputError("Solid/Box/Cells", "every count must be a whole number >= 1");
        }
      check_solid_cell_count(cell_counts[0] * cell_counts[1] * cell_counts[2], s.element, "Solid/Box/Cells");
      std::array<unsigned int, 3> cells{};
      for (int d = 0; d < 3; ++d) cells[d] = static_cast<unsigned int>(cell_counts[d]);
      s.mesh = generate_box(dealii::Point<3>(size[0], size[1], size[2]), cells);
    }
  const bool reduced = prm.get("Integration") == "reduced";
  s.gauss_points = (s.element == SolidElement::hex8 ? 2 : 3) - (reduced ? 1 : 0);

  for (const auto &[place, components] : base::named_items(prm.get("Supports"), entry, "node set or plane: components"))
    {
      SolidSupport support = parse_support_place(place, entry);
      support.text = place + ": " + components;
      if (support.plane_axis < 0 && !s.mesh->node_sets.count(support.node_set))
        {
          std::string names;
          for (const auto &[name, nodes] : s.mesh->node_sets) names += (names.empty() ? "" : ", ") + name;
          throw InputError(entry, "node set '" + base::printable_excerpt(support.node_set) + "' does not exist in " +
                                    s.mesh->source + "; allowed: " +
                                    (names.empty() ? "(the mesh has no node sets)" : base::printable_excerpt(names, 200)) +
                                    ", or a plane 'x = value'");
        }
      support.fixed = {{false, false, false}};
      for (const auto &c : base::split(components, ','))
        {
          if (c != "x" && c != "y" && c != "z")
            throw InputError(entry, "'" + base::printable_excerpt(c) + "' in '" + base::printable_excerpt(support.text) +
                                      "' is not a displacement component; allowed: x, y, z");
          support.fixed[c[0] - 'x'] = true;
        }
      s.supports.push_back(support);
    }
  s.material = Material::parse_parameters(prm, "Solid");
  prm.leave_subsection();
  return s;
}
} // namespace flextrack::fem
