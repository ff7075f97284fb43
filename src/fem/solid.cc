#include <fem/solid.h>
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
      std::array<double, 3> size{};
      std::array<unsigned int, 3> cells{};
      std::istringstream a(prm.get("Size")), b(prm.get("Cells"));
      std::string item;
      for (int d = 0; d < 3; ++d)
        {
          std::getline(a, item, ',');
          size[d] = std::stod(item);
          std::getline(b, item, ',');
          cells[d] = std::stoul(item);
          if (!(size[d] > 0)) throw InputError("Solid/Box/Size", "every edge length must be > 0 m");
        }
      prm.leave_subsection();
      s.mesh = generate_box(dealii::Point<3>(size[0], size[1], size[2]), cells);
    }
  const std::string element = prm.get("Element");
  s.element = element == "hex8" ? SolidElement::hex8 : element == "hex27" ? SolidElement::hex27 : SolidElement::hex20;
  const bool reduced = prm.get("Integration") == "reduced";
  s.gauss_points = (s.element == SolidElement::hex8 ? 2 : 3) - (reduced ? 1 : 0);

  std::istringstream list(prm.get("Supports"));
  std::string item;
  while (std::getline(list, item, ';'))
    {
      if (item.find_first_not_of(" \t") == std::string::npos) continue;
      const auto colon = item.find(':');
      if (colon == std::string::npos)
        throw InputError(entry, "'" + item + "' is not of the form 'node set or plane: components'");
      SolidSupport support;
      support.text = item;
      std::string where = item.substr(0, colon);
      where.erase(0, where.find_first_not_of(" \t"));
      where.erase(where.find_last_not_of(" \t") + 1);
      const auto eq = where.find('=');
      if (eq != std::string::npos)
        {
          std::string axis = where.substr(0, eq);
          axis.erase(axis.find_last_not_of(" \t") + 1);
          if (axis != "x" && axis != "y" && axis != "z")
            throw InputError(entry, "'" + where + "': a plane is 'x = value', 'y = value' or 'z = value' [m]");
          support.plane_axis = axis[0] - 'x';
          try { support.plane_position = std::stod(where.substr(eq + 1)); }
          catch (...) { throw InputError(entry, "'" + where + "': the plane position is not a number [m]"); }
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
      std::istringstream comps(item.substr(colon + 1));
      std::string c;
      while (std::getline(comps, c, ','))
        {
          c.erase(0, c.find_first_not_of(" \t"));
          c.erase(c.find_last_not_of(" \t") + 1);
          if (c != "x" && c != "y" && c != "z")
            throw InputError(entry, "'" + c + "' in '" + item + "' is not a displacement component; allowed: x, y, z");
          support.fixed[c[0] - 'x'] = true;
        }
      s.supports.push_back(support);
    }
  s.material = Material::parse_parameters(prm, "Solid");
  prm.leave_subsection();
  return s;
}
} // namespace flextrack::fem
