#include <fem/curved_beam_model.h>
#include <fem/solid_model.h>
#include <reduction/modal_participation.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/component_mask.h>

#include <map>

namespace flextrack::reduction
{
using namespace dealii;

namespace
{
/// The component of every dof of @p dofs.
template <int dim>
std::vector<unsigned int> dof_components(const DoFHandler<dim, 3> &dofs)
{
  std::vector<unsigned int> component(dofs.n_dofs(), 0);
  const unsigned int n = dofs.get_fe().n_components();
  for (unsigned int c = 0; c < n; ++c)
    {
      std::vector<bool> mask(n, false);
      mask[c] = true;
      for (const auto i : DoFTools::extract_dofs(dofs, ComponentMask(mask))) component[i] = c;
    }
  return component;
}
} // namespace

DofLayout dof_layout(const fem::CurvedBeamModel &arm)
{
  const auto &dofs = arm.dof_handler();
  const auto &fe = dofs.get_fe();
  const fem::Arm &description = arm.arm();
  DofLayout layout;
  layout.component = dof_components(dofs);
  layout.position.resize(dofs.n_dofs());
  // Nodes are keyed by the global index of their u_x dof (the cell-local numbering of FESystem
  // gives each node's six components the same base index).
  std::map<types::global_dof_index, DofLayout::SectionNode> nodes;
  const auto &unit_points = fe.get_unit_support_points();
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  for (const auto &cell : dofs.active_cell_iterators())
    {
      cell->get_dof_indices(local);
      const auto [s0, s1] = arm.mesh_of_arm().cell_arc_lengths(cell);
      // Local dofs of the same node: equal base index within their component.
      std::map<unsigned int, std::array<types::global_dof_index, 6>> node_dofs;
      std::map<unsigned int, double> node_s;
      for (unsigned int i = 0; i < local.size(); ++i)
        {
          const auto [c, base] = fe.system_to_component_index(i);
          node_dofs[base][c] = local[i];
          node_s[base] = s0 + unit_points[i][0] * (s1 - s0);
        }
      for (const auto &[base, six] : node_dofs)
        {
          if (nodes.count(six[0])) continue;
          const double s = node_s[base];
          const geometry::CurveGeometry g = description.curve->geometry(s);
          DofLayout::SectionNode node;
          node.dofs = six;
          node.t = g.tangent;
          node.y = description.frame->y_axis(g);
          node.z = cross_product_3d(node.t, node.y);
          for (const auto i : six) layout.position[i] = g.position;
          nodes.emplace(six[0], node);
        }
    }
  for (const auto &[first, node] : nodes) layout.section_nodes.push_back(node);
  return layout;
}

DofLayout dof_layout(const fem::SolidModel &solid)
{
  DofLayout layout;
  layout.component = dof_components(solid.dof_handler());
  layout.position = solid.support_points();
  return layout;
}

std::array<Vector<double>, 6> rigid_motions(const DofLayout &layout, const Point<3> &x_ref)
{
  const std::size_t n = layout.component.size();
  std::array<Vector<double>, 6> r;
  for (unsigned int d = 0; d < 6; ++d)
    {
      r[d].reinit(n);
      Tensor<1, 3> e;
      e[d % 3] = 1;
      for (std::size_t i = 0; i < n; ++i)
        {
          const unsigned int c = layout.component[i];
          if (d < 3)
            r[d][i] = c == d ? 1.0 : 0.0; // translation: displacement dofs of direction d
          else if (c < 3)
            r[d][i] = cross_product_3d(e, layout.position[i] - x_ref)[c]; // e_d x (x - x_ref)
          else
            r[d][i] = e[c - 3]; // a section rotation turns with the body: e_d
        }
    }
  return r;
}

unsigned int ModalParticipation::dominant_direction(const std::size_t k) const
{
  unsigned int best = 0;
  for (unsigned int d = 1; d < 6; ++d)
    if (fraction(k, d) > fraction(k, best)) best = d;
  return fraction(k, best) > 1e-3 ? best : 6;
}

MassProduct product_with(const TrilinosWrappers::SparseMatrix &M)
{
  return [&M](const Vector<double> &x, Vector<double> &y) { M.vmult(y, x); };
}

ModalParticipation modal_participation(const std::vector<Vector<double>> &shapes, const MassProduct &M,
                                       const DofLayout &layout, const Point<3> &x_ref)
{
  ModalParticipation p;
  p.reference_point = x_ref;
  const std::size_t n = layout.component.size();
  const auto r = rigid_motions(layout, x_ref);
  std::array<Vector<double>, 6> Mr;
  for (unsigned int d = 0; d < 6; ++d)
    {
      Mr[d].reinit(n);
      M(r[d], Mr[d]);
      p.total_mass[d] = r[d] * Mr[d];
    }
  for (const auto &phi : shapes)
    {
      std::array<double, 6> gamma{}, mass{};
      for (unsigned int d = 0; d < 6; ++d)
        {
          gamma[d] = phi * Mr[d];
          mass[d] = gamma[d] * gamma[d];
        }
      p.factors.push_back(gamma);
      p.effective_mass.push_back(mass);
    }
  return p;
}

namespace
{
/// Kinetic energies phi_c^T M phi_c of the four parts of an arm's mode (see the header).
std::array<double, 4> arm_energies(const Vector<double> &phi, const MassProduct &M,
                                   const std::vector<DofLayout::SectionNode> &nodes)
{
  std::array<Vector<double>, 4> part;
  for (auto &v : part) v.reinit(phi.size());
  for (const auto &node : nodes)
    {
      Tensor<1, 3> u, theta;
      for (unsigned int c = 0; c < 3; ++c)
        {
          u[c] = phi[node.dofs[c]];
          theta[c] = phi[node.dofs[3 + c]];
        }
      // (axial, in-plane, out-of-plane, torsion): displacement part, rotation part.
      const std::array<Tensor<1, 3>, 4> displacement = {{(u * node.t) * node.t, (u * node.y) * node.y,
                                                         (u * node.z) * node.z, Tensor<1, 3>()}};
      const std::array<Tensor<1, 3>, 4> rotation = {{Tensor<1, 3>(), (theta * node.z) * node.z,
                                                     (theta * node.y) * node.y, (theta * node.t) * node.t}};
      for (unsigned int k = 0; k < 4; ++k)
        for (unsigned int c = 0; c < 3; ++c)
          {
            part[k][node.dofs[c]] = displacement[k][c];
            part[k][node.dofs[3 + c]] = rotation[k][c];
          }
    }
  std::array<double, 4> energy{};
  Vector<double> Mv(phi.size());
  for (unsigned int k = 0; k < 4; ++k)
    {
      M(part[k], Mv);
      energy[k] = part[k] * Mv;
    }
  return energy;
}
} // namespace

std::vector<ModeClass> classify_modes(const std::vector<Vector<double>> &shapes, const MassProduct &M,
                                      const DofLayout &layout,
                                      const ModalParticipation &participation)
{
  std::vector<ModeClass> classes;
  for (std::size_t k = 0; k < shapes.size(); ++k)
    {
      ModeClass c;
      if (!layout.section_nodes.empty())
        {
          const auto e = arm_energies(shapes[k], M, layout.section_nodes);
          const double total = e[0] + e[1] + e[2] + e[3];
          unsigned int best = 0;
          for (unsigned int i = 0; i < 4; ++i)
            {
              c.energy_shares[i] = total > 0 ? e[i] / total : 0.0;
              if (e[i] > e[best]) best = i;
            }
          c.kind = arm_mode_kinds[best];
          c.share = c.energy_shares[best];
        }
      else
        {
          const unsigned int d = participation.dominant_direction(k);
          c.kind = d < 6 ? rigid_direction_names[d] : "-";
          c.share = d < 6 ? participation.fraction(k, d) : 0.0;
        }
      classes.push_back(c);
    }
  return classes;
}
} // namespace flextrack::reduction
