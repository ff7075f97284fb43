#include <fem/solid.h>
#include <base/text.h>

#include <cmath>
#include <base/input_error.h>

#include <sstream>

namespace flextrack::fem
{
using dealii::ParameterHandler;

void Solid::declare_parameters(ParameterHandler &prm)
{
  prm.enter_subsection("Solid");
  prm.declare_entry("Mesh", "box", dealii::Patterns::Selection("box|cylinder|file"),
                    "Where the hexahedral mesh comes from: 'box' or 'cylinder' (generated, see the subsections of "
                    "those names) or 'file' (Mesh file).");
  prm.declare_entry("Mesh file", "", dealii::Patterns::Anything(),
                    "Mesh file, relative to the parameter file, coordinates in m: Abaqus/CalculiX .inp (C3D8 or "
                    "C3D20 hexahedra, *NSET node sets) or Gmsh .msh (2.2 or 4.1 ASCII; 8- or 20-node hexahedra; "
                    "physical groups become node sets).");
  prm.enter_subsection("Box");
  prm.declare_entry("Size", "1, 0.1, 0.1", dealii::Patterns::List(dealii::Patterns::Double(0), 3, 3, ","),
                    "Edge lengths Lx, Ly, Lz [m] of the box [0, Lx] x [0, Ly] x [0, Lz]. Its node sets are "
                    "XMIN, XMAX, YMIN, YMAX, ZMIN, ZMAX (the nodes of each face).");
  prm.declare_entry("Cells", "10, 1, 1", dealii::Patterns::List(dealii::Patterns::Integer(1), 3, 3, ","),
                    "Number of cells along x, y, z [-].");
  prm.leave_subsection();
  prm.enter_subsection("Cylinder");
  prm.declare_entry("Radius", "0.05", dealii::Patterns::Double(0), "Radius R of the solid cylinder [m], > 0.");
  prm.declare_entry("Length", "1", dealii::Patterns::Double(0),
                    "Length L [m]: the axis runs along x from 0 to L. Node sets: HULL, XMIN, XMAX.");
  prm.declare_entry("Cells along the axis", "10", dealii::Patterns::Integer(1),
                    "Number of cells along the axis [-]; each cross-section has 5 cells.");
  prm.leave_subsection();
  prm.declare_entry("Element", "hex20", dealii::Patterns::Selection("hex20|hex8|hex27"),
                    "Finite element: 'hex20' (20-node serendipity, seed eq. 30, as CalculiX C3D20), 'hex8' "
                    "(deal.II FE_Q(1)), 'hex27' (deal.II FE_Q(2)). The geometry is always the 20-node map.");
  prm.declare_entry("Integration", "full", dealii::Patterns::Selection("full|reduced"),
                    "Gauss rule per direction: 'full' = 3 points (hex8: 2), 'reduced' = 2 points (hex8: 1).");
  prm.declare_entry("Supports", "XMIN: x, y, z", dealii::Patterns::Anything(),
                    "Fixed displacement components, ';'-separated, each 'WHERE: components' with WHERE a node "
                    "set name or a plane 'x = 0.0' [m], and components from x, y, z; e.g. 'XMIN: x, y, z; "
                    "y = 0: y'. Empty: a free body (six zero-frequency modes).");
  Material::declare_parameters(prm);
  prm.leave_subsection();
}

Solid Solid::parse_parameters(ParameterHandler &prm, const std::string &directory)
{
  Solid s;
  prm.enter_subsection("Solid");
  const std::string entry = "Solid/Supports";
  if (prm.get("Mesh") == "file")
    {
      std::string file = prm.get("Mesh file");
      if (!file.empty() && file[0] != '/') file = directory + "/" + file;
      s.mesh = read_mesh_file(file, "Solid/Mesh file");
    }
  else if (prm.get("Mesh") == "cylinder")
    {
      prm.enter_subsection("Cylinder");
      const double R = prm.get_double("Radius"), L = prm.get_double("Length");
      const unsigned int n = prm.get_integer("Cells along the axis");
      prm.leave_subsection();
      if (!(R > 0)) throw InputError("Solid/Cylinder/Radius", "must be > 0 m");
      if (!(L > 0)) throw InputError("Solid/Cylinder/Length", "must be > 0 m");
      s.mesh = generate_cylinder(R, L, n);
    }
  else
    {
      prm.enter_subsection("Box");
      const std::array<double, 3> size = base::parse_vector3(prm.get("Size"), "Solid/Box/Size", "m");
      const auto cell_counts = base::parse_vector3(prm.get("Cells"), "Solid/Box/Cells", "-");
      std::array<unsigned int, 3> cells{};
      // A bound on the count keeps a typo (2147483647) from exhausting memory: 1e6 hex20 cells
      // are about 1.3e7 degrees of freedom, beyond what a direct solver handles here.
      constexpr double max_cells = 1e6;
      for (int d = 0; d < 3; ++d)
        {
          if (!(cell_counts[d] >= 1 && cell_counts[d] <= max_cells && cell_counts[d] == std::floor(cell_counts[d])))
            throw InputError("Solid/Box/Cells", "every count must be a whole number from 1 to 1000000");
          cells[d] = static_cast<unsigned int>(cell_counts[d]);
          if (!(size[d] > 0)) throw InputError("Solid/Box/Size", "every edge length must be > 0 m");
        }
      if (cell_counts[0] * cell_counts[1] * cell_counts[2] > max_cells)
        throw InputError("Solid/Box/Cells", "more than 1000000 cells in all (" +
                                              std::to_string(cell_counts[0] * cell_counts[1] * cell_counts[2]) + ")");
      prm.leave_subsection();
      s.mesh = generate_box(dealii::Point<3>(size[0], size[1], size[2]), cells);
    }
  const std::string element = prm.get("Element");
  s.element = element == "hex8" ? SolidElement::hex8 : element == "hex27" ? SolidElement::hex27 : SolidElement::hex20;
  const bool reduced = prm.get("Integration") == "reduced";
  s.gauss_points = (s.element == SolidElement::hex8 ? 2 : 3) - (reduced ? 1 : 0);

  for (const auto &[place, components] : base::named_items(prm.get("Supports"), entry, "node set or plane: components"))
    {
      SolidSupport support;
      support.text = place + ": " + components;
      std::string where = place;
      const auto eq = where.find('=');
      if (eq != std::string::npos)
        {
          const std::string axis = base::trim(where.substr(0, eq));
          if (axis != "x" && axis != "y" && axis != "z")
            throw InputError(entry, "'" + where + "': a plane is 'x = value', 'y = value' or 'z = value' [m]");
          support.plane_axis = axis[0] - 'x';
          support.plane_position = base::parse_number(where.substr(eq + 1), entry, "the plane position [m]");
        }
      else
        {
          for (auto &c : where) c = std::toupper(static_cast<unsigned char>(c));
          if (!s.mesh->node_sets.count(where))
            {
              std::string names;
              for (const auto &[name, nodes] : s.mesh->node_sets) names += (names.empty() ? "" : ", ") + name;
              throw InputError(entry, "node set '" + where + "' does not exist in " + s.mesh->source +
                               "; allowed: " + (names.empty() ? "(the mesh has no node sets)" : names) +
                               ", or a plane 'x = value'");
            }
          support.node_set = where;
        }
      support.fixed = {false, false, false};
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
