#include <base/input_error.h>
#include <reduction/arm_geometry.h>
#include <reduction/inertia_invariants_builder.h>
#include <reduction/reduced_body_builder.h>

#include <algorithm>
#include <sstream>
#include <map>
#include <tuple>

namespace flextrack::reduction
{
using namespace dealii;

namespace
{
/// The arm's exact curve and section frame, and the text that rebuilds them in a reduced body
/// file; the text is rebuilt here once, so that a file that cannot be read back is never written.
void set_arm_geometry(const fem::Arm &arm, ArmModeData &d)
{
  d.curve = arm.curve;
  d.frame = arm.frame;
  d.geometry_parameters = arm.geometry_parameters;
  d.section_outline = arm.section.outline();
  if (d.geometry_parameters.empty()) return; // an arm built in code: the file will not know its curve
  try
    {
      const auto rebuilt = parse_arm_geometry(d.geometry_parameters);
      check_arm_geometry(*rebuilt.curve, d);
      // The frame follows from the curve and the frame entries; compare it where nodes are.
      for (unsigned int c = 0; c < d.n_cells(); ++c)
        for (const double x : d.xi)
          {
            const double s = std::min(d.cell_s[c] + x * (d.cell_s[c + 1] - d.cell_s[c]), d.length());
            if (!((rebuilt.frame->y_axis(s) - d.frame->y_axis(s)).norm() <= 1e-9))
              {
                std::ostringstream m;
                m << "the section frame rebuilt from its parameter text differs from the arm's at s = " << s << " m";
                throw std::runtime_error(m.str());
              }
          }
    }
  catch (const std::runtime_error &e)
    {
      throw InputError(arm.section_name + "/Curve",
                       std::string("the curve and section frame cannot be stored in the reduced body as parameter "
                                   "text (") + e.what() + ")");
    }
}

/// Mode fields of arm @p a: FE nodal values of every cell, in order of arc length.
ArmModeData arm_mode_data(const fem::BodyModel &model, const unsigned int a, const std::vector<Vector<double>> &full)
{
  const auto &arm = model.arm_model(a);
  const auto &fe = arm.dof_handler().get_fe();
  const auto &base = fe.base_element(0);
  ArmModeData d;
  d.name = model.arm_name(a);
  d.n_modes = full.size();
  for (const auto &q : base.get_unit_support_points()) d.xi.push_back(q[0]);
  std::vector<std::tuple<double, double, DoFHandler<1, 3>::active_cell_iterator>> cells;
  for (const auto &cell : arm.dof_handler().active_cell_iterators())
    {
      const auto [s0, s1] = arm.mesh_of_arm().cell_arc_lengths(cell);
      cells.emplace_back(s0, s1, cell);
    }
  std::sort(cells.begin(), cells.end(), [](const auto &x, const auto &y) { return std::get<0>(x) < std::get<0>(y); });
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  d.cell_s.push_back(0.0);
  const double L = arm.arm().curve->length();
  for (const auto &[s0, s1, cell] : cells)
    {
      d.cell_s.push_back(std::min(s1, L));
      cell->get_dof_indices(local);
      for (unsigned int j = 0; j < d.xi.size(); ++j)
        {
          const Point<3> x = arm.arm().curve->position(std::min(s0 + d.xi[j] * (s1 - s0), L));
          for (unsigned int c = 0; c < 3; ++c) d.positions.push_back(x[c]);
          for (const auto &phi : full)
            for (unsigned int c = 0; c < 6; ++c)
              d.values.push_back(phi[model.arm_offset(a) + local[fe.component_to_system_index(c, j)]]);
        }
    }
  d.cell_s.back() = L;
  set_arm_geometry(arm.arm(), d);
  return d;
}
} // namespace

ReducedBody make_reduced_body(const fem::BodyModel &model, const ReducedBasis &basis, const std::string &method)
{
  ReducedBody r;
  r.method = method;
  r.n_full_dofs = model.n_full_dofs();
  r.n_body_dofs = model.n_dofs();
  r.n_normal = basis.n_normal;
  r.n_interface = basis.n_interface;
  r.n_track = basis.n_track;
  r.stiffness = basis.stiffness;
  r.mass = basis.mass;
  r.damping = basis.damping;
  r.frequencies_hz = basis.frequencies_hz();
  r.geometric_stiffness = basis.geometric_stiffness;
  const unsigned int n = basis.modes.size();
  std::vector<Vector<double>> full;
  for (const auto &phi : basis.modes) full.push_back(model.expand(phi));
  r.invariants = compute_inertia_invariants_of_expanded(model, full);

  for (const auto &p : model.interfaces())
    {
      ReducedBody::Interface i{p.name, p.position, FullMatrix<double>(6, n)};
      for (unsigned int k = 0; k < n; ++k)
        for (unsigned int c = 0; c < 6; ++c) i.modes(c, k) = basis.modes[k][p.dofs[c]];
      r.interfaces.push_back(i);
    }

  for (const auto &p : model.output_points())
    {
      ReducedBody::Interface o{p.name, p.position, FullMatrix<double>(6, n)};
      for (unsigned int k = 0; k < n; ++k)
        for (unsigned int c = 0; c < 6; ++c) o.modes(c, k) = full[k][p.full_dofs[c]];
      r.output_points.push_back(o);
    }
  for (unsigned int a = 0; a < model.n_arms(); ++a)
    {
      r.arms.push_back(arm_mode_data(model, a, full));
      r.arms.back().track_stations = a < basis.track_stations.size() ? basis.track_stations[a] : 0;
    }
  for (const auto &m : model.body().point_masses)
    for (unsigned int i = 0; i < r.interfaces.size(); ++i)
      if (r.interfaces[i].name == m.interface) r.point_masses.emplace_back(i, m.mass);

  // Drawing: the solid's boundary faces as quadratic quads (linear elements repeat corners at
  // the mid-sides), the arms' centre lines as segments between nodes.
  const auto &nodes = model.full_nodes();
  std::map<unsigned int, unsigned int> point_of_node;
  auto point = [&](const unsigned int node) {
    const auto [it, added] = point_of_node.emplace(node, r.points.size());
    if (added) r.points.push_back(nodes[node].x);
    return it->second;
  };
  if (const auto *solid = model.solid_model())
    for (const auto &cell : solid->dof_handler().active_cell_iterators())
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            const auto face = cell->face(f);
            const unsigned int corner[4] = {0, 1, 3, 2}; // deal.II lexicographic -> counter-clockwise
            std::array<unsigned int, 8> q;
            for (unsigned int v = 0; v < 4; ++v) q[v] = point(model.node_of_solid(face->vertex_dof_index(corner[v], 0)));
            for (unsigned int e = 0; e < 4; ++e)
              {
                const unsigned int va = face->vertex_index(corner[e]), vb = face->vertex_index(corner[(e + 1) % 4]);
                q[4 + e] = q[e];
                if (face->get_fe(0).n_dofs_per_line() == 0) continue;
                for (unsigned int l = 0; l < 4; ++l)
                  {
                    const auto line = face->line(l);
                    if ((line->vertex_index(0) == va && line->vertex_index(1) == vb) ||
                        (line->vertex_index(0) == vb && line->vertex_index(1) == va))
                      q[4 + e] = point(model.node_of_solid(line->dof_index(0)));
                  }
              }
            r.quads.push_back(q);
          }
  // Arm centre lines: every arm node in order of s (vertex 0, interior nodes, vertex 1 of each
  // cell; shared vertices once), joined by segments.
  const unsigned int n_solid_points = r.points.size();
  std::vector<std::pair<unsigned int, unsigned int>> arm_points; // (arm, node in ArmModeData)
  for (unsigned int a = 0; a < r.arms.size(); ++a)
    {
      const auto &arm = r.arms[a];
      const unsigned int per_cell = arm.xi.size();
      std::vector<unsigned int> order(per_cell);
      for (unsigned int j = 0; j < per_cell; ++j) order[j] = j;
      std::sort(order.begin(), order.end(), [&](unsigned int x, unsigned int y) { return arm.xi[x] < arm.xi[y]; });
      for (unsigned int c = 0; c < arm.n_cells(); ++c)
        for (unsigned int o = (c == 0 ? 0 : 1); o < per_cell; ++o)
          {
            const unsigned int node = c * per_cell + order[o];
            if (!(c == 0 && o == 0)) r.lines.push_back({{static_cast<unsigned int>(r.points.size() - 1),
                                                         static_cast<unsigned int>(r.points.size())}});
            r.points.emplace_back(arm.positions[3 * node], arm.positions[3 * node + 1], arm.positions[3 * node + 2]);
            arm_points.emplace_back(a, node);
          }
    }
  const unsigned int P = r.points.size();
  r.point_modes.assign(n * P * 3, 0.0);
  for (unsigned int k = 0; k < n; ++k)
    {
      for (const auto &[node, i] : point_of_node)
        for (unsigned int d = 0; d < 3; ++d) r.point_modes[(k * P + i) * 3 + d] = full[k][nodes[node].u[d]];
      for (unsigned int m = 0; m < arm_points.size(); ++m)
        {
          const auto &[a, node] = arm_points[m];
          for (unsigned int d = 0; d < 3; ++d)
            r.point_modes[(k * P + n_solid_points + m) * 3 + d] = r.arms[a].values[(node * n + k) * 6 + d];
        }
    }
  return r;
}
} // namespace flextrack::reduction
