#include <base/input_error.h>
#include <fem/curved_beam_model.h>
#include <fem/symmetric_assembly.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/base/table.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>

#include <algorithm>
#include <array>
#include <map>

namespace flextrack::fem
{
using namespace dealii;

namespace
{
/// Section frame (t, y, z) at one quadrature point.
struct SectionAxes
{
  Tensor<1, 3> t, y, z;
};

SectionAxes section_axes(const Arm &arm, const double s)
{
  SectionAxes a;
  a.t = arm.curve->geometry(s).tangent;
  a.y = arm.frame->y_axis(s);
  a.z = cross_product_3d(a.t, a.y);
  return a;
}

/// Strain vector [Gamma_t, Gamma_y, Gamma_z, kappa_t, kappa_y, kappa_z] of one shape function.
std::array<double, 6> strains(const SectionAxes &a, const unsigned int component, const double N, const double dN)
{
  if (component < 3)
    return {{a.t[component] * dN, a.y[component] * dN, a.z[component] * dN, 0, 0, 0}};
  const unsigned int c = component - 3; // t x e_c in section axes: (0, -z_c, y_c)
  return {{0, -a.z[c] * N, a.y[c] * N, a.t[c] * dN, a.y[c] * dN, a.z[c] * dN}};
}
} // namespace

CurvedBeamModel::CurvedBeamModel(const Arm &arm, const unsigned int refinement, const bool constrain_matrices)
try : description(arm), constrained_assembly(constrain_matrices), mesh(arm, refinement), fe(FE_Q<1, 3>(arm.degree), 6),
    map(std::make_unique<MappingQ<1, 3>>(std::max(arm.degree, 3u))), dofs(mesh.triangulation())
{
  setup_dofs();
  apply_supports();
  assemble();
}
catch (const geometry::FrameError &e)
{
  // The section frame is evaluated along the whole arm only here: name the arm's entry.
  throw InputError(arm.section_name + "/Section frame/Kind", e.what());
}

void CurvedBeamModel::setup_dofs() { dofs.distribute_dofs(fe); }

std::array<double, 6> CurvedBeamModel::section_stiffness() const
{
  const Material &m = description.material;
  const CrossSection &x = description.section;
  return {{m.youngs_modulus * x.area, x.shear_factor_y * m.shear_modulus * x.area,
           x.shear_factor_z * m.shear_modulus * x.area, m.shear_modulus * x.torsion_constant,
           m.youngs_modulus * x.inertia_y, m.youngs_modulus * x.inertia_z}};
}

SectionForces CurvedBeamModel::section_forces_in(const DoFHandler<1, 3>::active_cell_iterator &cell, const double xi,
                                                 const Vector<double> &u) const
{
  const auto [s0, s1] = mesh.cell_arc_lengths(cell);
  const double h = s1 - s0;
  const SectionAxes a = section_axes(description, s0 + h * xi);
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  cell->get_dof_indices(local);
  std::array<double, 6> e{};
  for (unsigned int i = 0; i < local.size(); ++i)
    {
      const unsigned int c = fe.system_to_component_index(i).first;
      const auto B = strains(a, c, fe.shape_value_component(i, Point<1>(xi), c),
                             fe.shape_grad_component(i, Point<1>(xi), c)[0] / h);
      for (unsigned int k = 0; k < 6; ++k) e[k] += B[k] * u[local[i]];
    }
  const auto D = section_stiffness();
  SectionForces f;
  f.s = s0 + h * xi;
  for (unsigned int k = 0; k < 6; ++k) f.values[k] = D[k] * e[k];
  return f;
}

std::vector<SectionForces> CurvedBeamModel::section_forces(const Vector<double> &u) const
{
  // Per cell in the order of s: its start, its p Gauss points (the reduced rule of the stiffness,
  // where the section forces are most accurate) and its end.
  std::vector<std::pair<double, DoFHandler<1, 3>::active_cell_iterator>> cells;
  for (const auto &cell : dofs.active_cell_iterators()) cells.emplace_back(mesh.cell_arc_lengths(cell).first, cell);
  std::sort(cells.begin(), cells.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
  const QGauss<1> rule(description.degree);
  std::vector<SectionForces> samples;
  for (const auto &[s0, cell] : cells)
    {
      samples.push_back(section_forces_in(cell, 0.0, u));
      for (unsigned int q = 0; q < rule.size(); ++q) samples.push_back(section_forces_in(cell, rule.point(q)[0], u));
      samples.push_back(section_forces_in(cell, 1.0, u));
    }
  return samples;
}

Vector<double> CurvedBeamModel::section_force_field(const Vector<double> &u) const
{
  // Each cell's values at its nodes, averaged where cells meet (a point load's jump in the
  // shear force is drawn as a linear change over the neighbouring cells).
  // The six components share the nodes of the scalar element: evaluate once per node.
  Vector<double> field(dofs.n_dofs()), count(dofs.n_dofs());
  const auto &nodes = fe.base_element(0).get_unit_support_points();
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  for (const auto &cell : dofs.active_cell_iterators())
    {
      cell->get_dof_indices(local);
      std::vector<SectionForces> at_node;
      for (const auto &x : nodes) at_node.push_back(section_forces_in(cell, x[0], u));
      for (unsigned int i = 0; i < local.size(); ++i)
        {
          const auto [c, node] = fe.system_to_component_index(i);
          field[local[i]] += at_node[node].values[c];
          count[local[i]] += 1;
        }
    }
  for (unsigned int i = 0; i < field.size(); ++i) field[i] /= count[i];
  return field;
}

void CurvedBeamModel::apply_supports()
{
  // Each support station is a mesh vertex; fix its 3 displacements (pinned) or all 6 dofs.
  std::map<unsigned int, unsigned int> fixed_per_vertex; // vertex -> number of fixed components
  for (const auto &support : description.supports)
    {
      const unsigned int n = support.kind == SupportKind::clamped ? 6 : support.kind == SupportKind::pinned ? 3 : 0;
      unsigned int &current = fixed_per_vertex[mesh.vertex_at(support.s)];
      current = std::max(current, n);
    }
  for (const auto &cell : dofs.active_cell_iterators())
    for (unsigned int v = 0; v < 2; ++v)
      if (const auto it = fixed_per_vertex.find(cell->vertex_index(v)); it != fixed_per_vertex.end())
        for (unsigned int c = 0; c < it->second; ++c)
          {
            const auto dof = cell->vertex_dof_index(v, c);
            if (!supports.is_constrained(dof)) supports.add_line(dof);
          }
  supports.close();
}

void CurvedBeamModel::assemble()
{
  AffineConstraints<double> none;
  none.close();
  const AffineConstraints<double> &applied = constrained_assembly ? supports : none;
  DynamicSparsityPattern pattern(dofs.n_dofs());
  DoFTools::make_sparsity_pattern(dofs, pattern, applied, false);
  stiffness.reinit(pattern);
  mass.reinit(pattern);

  const CrossSection &x = description.section;
  const std::array<double, 6> D = section_stiffness();
  const double rho = description.material.density;

  const unsigned int p = description.degree, n = fe.n_dofs_per_cell();
  const QGauss<1> stiffness_rule(p), mass_rule(p + 1);
  // Shape functions on the reference cell [0, 1]; a cell spans arc lengths [s0, s1] of the
  // exact curve, so d/ds = (1 / (s1 - s0)) d/dxi and ds = (s1 - s0) dxi.
  auto tabulate = [&](const QGauss<1> &rule, Table<2, double> &N, Table<2, double> &dN) {
    N.reinit(n, rule.size());
    dN.reinit(n, rule.size());
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int q = 0; q < rule.size(); ++q)
        {
          const unsigned int c = fe.system_to_component_index(i).first;
          N(i, q) = fe.shape_value_component(i, rule.point(q), c);
          dN(i, q) = fe.shape_grad_component(i, rule.point(q), c)[0];
        }
  };
  Table<2, double> Nk, dNk, Nm, dNm;
  tabulate(stiffness_rule, Nk, dNk);
  tabulate(mass_rule, Nm, dNm);
  std::vector<unsigned int> component(n);
  for (unsigned int i = 0; i < n; ++i) component[i] = fe.system_to_component_index(i).first;

  FullMatrix<double> k_cell(n, n), m_cell(n, n);
  std::vector<types::global_dof_index> cell_dofs(n);
  std::vector<std::array<double, 6>> B(n);

  for (const auto &cell : dofs.active_cell_iterators())
    {
      const auto [s0, s1] = mesh.cell_arc_lengths(cell);
      const double h = s1 - s0;
      k_cell = 0;
      m_cell = 0;

      // Stiffness integrand: B^T D B.
      for (unsigned int q = 0; q < stiffness_rule.size(); ++q)
        {
          const double s = s0 + h * stiffness_rule.point(q)[0];
          const SectionAxes a = section_axes(description, s);
          for (unsigned int i = 0; i < n; ++i)
            B[i] = strains(a, component[i], Nk(i, q), dNk(i, q) / h);
          const double dx = h * stiffness_rule.weight(q);
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = 0; j <= i; ++j)
              {
                double v = 0;
                for (int k = 0; k < 6; ++k) v += B[i][k] * D[k] * B[j][k];
                k_cell(i, j) += v * dx;
              }
        }

      // Mass integrand: rho A for displacements, rho (Ip t t + Iy y y + Iz z z) for rotations.
      for (unsigned int q = 0; q < mass_rule.size(); ++q)
        {
          const double s = s0 + h * mass_rule.point(q)[0];
          const SectionAxes a = section_axes(description, s);
          const double dx = h * mass_rule.weight(q);
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = 0; j <= i; ++j)
              {
                const unsigned int ci = component[i], cj = component[j];
                const double NN = Nm(i, q) * Nm(j, q) * dx;
                if (ci < 3 && cj < 3)
                  m_cell(i, j) += ci == cj ? rho * x.area * NN : 0.0;
                else if (ci >= 3 && cj >= 3)
                  {
                    const unsigned int u = ci - 3, w = cj - 3;
                    m_cell(i, j) += rho * NN * (x.polar_inertia * a.t[u] * a.t[w] + x.inertia_y * a.y[u] * a.y[w] +
                                                x.inertia_z * a.z[u] * a.z[w]);
                  }
              }
        }
      cell->get_dof_indices(cell_dofs);
      add_symmetric_cell_matrices(k_cell, m_cell, cell_dofs, applied, stiffness, mass);
    }
  finish_assembly(applied, stiffness, mass);
}

void CurvedBeamModel::geometric_stiffness(const Vector<double> &u, TrilinosWrappers::SparseMatrix &K_G) const
{
  K_G.reinit(stiffness);
  const double EA = description.material.youngs_modulus * description.section.area;
  const unsigned int n = fe.n_dofs_per_cell();
  // p + 1 Gauss points integrate N u' v' exactly (degree 3p - 3 <= 2p + 1 for p <= 3).
  const QGauss<1> rule(description.degree + 1);
  std::vector<unsigned int> component(n);
  Table<2, double> dN(n, rule.size());
  for (unsigned int i = 0; i < n; ++i)
    {
      component[i] = fe.system_to_component_index(i).first;
      for (unsigned int q = 0; q < rule.size(); ++q) dN(i, q) = fe.shape_grad_component(i, rule.point(q), component[i])[0];
    }
  FullMatrix<double> g_cell(n, n);
  std::vector<types::global_dof_index> cell_dofs(n);
  for (const auto &cell : dofs.active_cell_iterators())
    {
      const auto [s0, s1] = mesh.cell_arc_lengths(cell);
      const double h = s1 - s0;
      cell->get_dof_indices(cell_dofs);
      g_cell = 0;
      for (unsigned int q = 0; q < rule.size(); ++q)
        {
          const SectionAxes a = section_axes(description, s0 + h * rule.point(q)[0]);
          Tensor<1, 3> du; // u' at the point
          for (unsigned int i = 0; i < n; ++i)
            if (component[i] < 3) du[component[i]] += dN(i, q) / h * u[cell_dofs[i]];
          const double N = EA * (a.t[0] * du[0] + a.t[1] * du[1] + a.t[2] * du[2]);
          const double dx = h * rule.weight(q);
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = 0; j < n; ++j)
              {
                const unsigned int ci = component[i], cj = component[j];
                if (ci >= 3 || cj >= 3) continue;
                const double projector = (ci == cj ? 1.0 : 0.0) - a.t[ci] * a.t[cj];
                g_cell(i, j) += N * (dN(i, q) / h) * (dN(j, q) / h) * projector * dx;
              }
        }
      K_G.add(cell_dofs, g_cell);
    }
  K_G.compress(VectorOperation::add);
}

std::pair<DoFHandler<1, 3>::active_cell_iterator, double> CurvedBeamModel::locate(const double s) const
{
  for (const auto &cell : dofs.active_cell_iterators())
    {
      const auto [s0, s1] = mesh.cell_arc_lengths(cell);
      if (s >= s0 && s <= s1) return {cell, (s - s0) / (s1 - s0)};
    }
  throw std::out_of_range("arc length " + std::to_string(s) + " m is not on the arm");
}

Vector<double> CurvedBeamModel::point_load(const double s, const Tensor<1, 3> &F) const
{
  const auto [cell, xi] = locate(s);
  Vector<double> f(dofs.n_dofs());
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  cell->get_dof_indices(local);
  for (unsigned int i = 0; i < local.size(); ++i)
    {
      const unsigned int c = fe.system_to_component_index(i).first;
      if (c < 3) f[local[i]] += F[c] * fe.shape_value_component(i, Point<1>(xi), c);
    }
  supports.set_zero(f);
  return f;
}

Tensor<1, 3> CurvedBeamModel::field_at(const double s, const Vector<double> &u, const unsigned int c0) const
{
  const auto [cell, xi] = locate(s);
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  cell->get_dof_indices(local);
  Tensor<1, 3> d;
  for (unsigned int i = 0; i < local.size(); ++i)
    {
      const unsigned int c = fe.system_to_component_index(i).first;
      if (c >= c0 && c < c0 + 3) d[c - c0] += u[local[i]] * fe.shape_value_component(i, Point<1>(xi), c);
    }
  return d;
}

Tensor<1, 3> CurvedBeamModel::displacement_at(const double s, const Vector<double> &u) const { return field_at(s, u, 0); }

Tensor<1, 3> CurvedBeamModel::rotation_at(const double s, const Vector<double> &u) const { return field_at(s, u, 3); }

void CurvedBeamModel::add_point_load(const double s, const Tensor<1, 3> &F, const Tensor<1, 3> &M, Vector<double> &f) const
{
  const auto [cell, xi] = locate(s);
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  cell->get_dof_indices(local);
  for (unsigned int i = 0; i < local.size(); ++i)
    {
      const unsigned int c = fe.system_to_component_index(i).first;
      f[local[i]] += (c < 3 ? F[c] : M[c - 3]) * fe.shape_value_component(i, Point<1>(xi), c);
    }
}

void CurvedBeamModel::add_line_load(const double s0, const double s1, const Tensor<1, 3> &q, Vector<double> &f) const
{
  // Per cell, Gauss points on the part of [s0, s1] it covers: p + 1 points integrate the
  // polynomial shape functions exactly. A ring's cell across the seam spans [c0, c1 + L].
  const double L = description.curve->length();
  const QGauss<1> rule(description.degree + 1);
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  for (const auto &cell : dofs.active_cell_iterators())
    {
      const auto [c0, c1] = mesh.cell_arc_lengths(cell);
      cell->get_dof_indices(local);
      for (const double shift : {0.0, description.curve->is_closed() ? L : -1.0})
        {
          if (shift < 0) continue;
          const double a = std::max(c0, s0 + shift), b = std::min(c1, s1 + shift);
          if (!(b > a)) continue;
          for (unsigned int k = 0; k < rule.size(); ++k)
            {
              const double s = a + (b - a) * rule.point(k)[0], ds = (b - a) * rule.weight(k);
              const Point<1> xi((s - c0) / (c1 - c0));
              for (unsigned int i = 0; i < local.size(); ++i)
                {
                  const unsigned int c = fe.system_to_component_index(i).first;
                  if (c < 3) f[local[i]] += q[c] * fe.shape_value_component(i, xi, c) * ds;
                }
            }
        }
    }
}

Vector<double> CurvedBeamModel::load_vector(const LoadCase &load_case) const
{
  Vector<double> f(dofs.n_dofs());
  for (const auto &p : load_case.point_forces) add_point_load(p.s, p.value, Tensor<1, 3>(), f);
  for (const auto &p : load_case.point_moments) add_point_load(p.s, Tensor<1, 3>(), p.value, f);
  for (const auto &l : load_case.line_loads) add_line_load(l.s0, l.s1, l.q, f);
  if (load_case.gravity.norm() > 0)
    add_line_load(0, description.curve->length(),
                  description.material.density * description.section.area * load_case.gravity, f);
  return f;
}

Vector<double> CurvedBeamModel::support_displacements(const LoadCase &load_case) const
{
  Vector<double> g(dofs.n_dofs());
  std::map<unsigned int, const SupportDisplacement *> at_vertex; // one item per support station
  for (const auto &d : load_case.support_displacements)
    {
      const unsigned int vertex = mesh.vertex_at(d.s);
      if (const auto it = at_vertex.find(vertex); it != at_vertex.end() && it->second->value != d.value)
        throw InputError("Load case " + load_case.name + "/Support displacements",
                         "'" + it->second->label + "' and '" + d.label +
                           "' are the same support station with different displacements; allowed: one value per support");
      at_vertex[vertex] = &d;
      for (const auto &cell : dofs.active_cell_iterators())
        for (unsigned int v = 0; v < 2; ++v)
          if (cell->vertex_index(v) == vertex)
            for (unsigned int c = 0; c < d.value.size(); ++c) g[cell->vertex_dof_index(v, c)] = d.value[c];
    }
  return g;
}

Resultant CurvedBeamModel::vertex_resultant(const Vector<double> &r) const
{
  Resultant total;
  std::vector<bool> done(mesh.triangulation().n_vertices(), false);
  for (const auto &cell : dofs.active_cell_iterators())
    for (unsigned int v = 0; v < 2; ++v)
      {
        if (done[cell->vertex_index(v)]) continue;
        done[cell->vertex_index(v)] = true;
        Tensor<1, 3> F, M;
        for (unsigned int c = 0; c < 3; ++c)
          {
            F[c] = r[cell->vertex_dof_index(v, c)];
            M[c] = r[cell->vertex_dof_index(v, c + 3)];
          }
        total.force += F;
        total.moment += cross_product_3d(Tensor<1, 3>(cell->vertex(v)), F) + M;
      }
  return total;
}
} // namespace flextrack::fem
