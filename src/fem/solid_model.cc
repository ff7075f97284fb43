#include <fem/fe_serendipity.h>
#include <fem/solid_model.h>
#include <fem/symmetric_assembly.h>
#include <base/input_error.h>
#include <base/memory.h>
#include <base/mpi_session.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>

namespace flextrack::fem
{
using namespace dealii;

namespace
{
std::unique_ptr<FESystem<3>> make_element(const SolidElement kind)
{
  switch (kind)
    {
      case SolidElement::hex8: return std::make_unique<FESystem<3>>(FE_Q<3>(1), 3);
      case SolidElement::hex27: return std::make_unique<FESystem<3>>(FE_Q<3>(2), 3);
      default: return std::make_unique<FESystem<3>>(FE_Serendipity<3>(), 3);
    }
}

/// Reference coordinates, in the coarse ancestor of @p cell, of the point @p p of @p cell.
/// A plain (not active) cell iterator: it walks up to parents, which are not active.
Point<3> coarse_coordinates(Triangulation<3>::cell_iterator cell, Point<3> p)
{
  while (cell->level() > 0)
    {
      const auto parent = cell->parent();
      unsigned int child = 0;
      while (parent->child(child) != cell) ++child;
      p = GeometryInfo<3>::child_to_cell_coordinates(p, child);
      cell = parent;
    }
  return p;
}
} // namespace

SolidModel::SolidModel(const Solid &solid, const unsigned int refinement, const bool constrain_matrices,
                       const bool with_mass, const MPI_Comm communicator)
  : body(solid), level(refinement), constrained_assembly(constrain_matrices), assemble_mass(with_mass),
    tria(communicator, Triangulation<3>::none, false, parallel::shared::Triangulation<3>::partition_metis),
    geometry_fe(FE_Serendipity<3>(), 3), fe(make_element(solid.element))
{
  tria.copy_triangulation(body.mesh->triangulation);
  // Faces whose nodes all belong to a node set carry a boundary id, inherited on refinement,
  // so that node sets of whole faces apply on refined meshes too.
  if (refinement > 0)
    {
      types::boundary_id id = 1;
      for (const auto &[name, nodes] : body.mesh->node_sets)
        {
          const std::set<MeshNode> set(nodes.begin(), nodes.end());
          for (const auto &cell : tria.active_cell_iterators())
            for (const auto f : cell->face_indices())
              if (cell->face(f)->at_boundary())
                {
                  bool all = true;
                  for (unsigned int v = 0; v < 4; ++v) all &= set.count(MeshNode{true, cell->face(f)->vertex_index(v), {0, 0}}) > 0;
                  if (all) cell->face(f)->set_boundary_id(id);
                }
          ++id;
        }
      tria.refine_global(refinement);
    }
  setup_geometry();
  dofs.reinit(tria);
  dofs.distribute_dofs(*fe);
  tabulate_node_dofs();
  apply_supports();
  assemble();
}

void SolidModel::setup_geometry()
{
  // Positions of the 20 geometry nodes of every cell, from its coarse ancestor's 20-node map.
  geometry_dofs.reinit(tria);
  geometry_dofs.distribute_dofs(geometry_fe);
  positions.reinit(geometry_dofs.n_dofs());
  const SerendipityPolynomials N;
  const auto reference = SerendipityPolynomials::nodes();
  const auto &mesh = *body.mesh;
  std::vector<types::global_dof_index> local(geometry_fe.n_dofs_per_cell());
  for (const auto &cell : geometry_dofs.active_cell_iterators())
    {
      // The coarse ancestor: a plain cell iterator, since an active one may not point to a parent.
      Triangulation<3>::cell_iterator coarse = cell;
      while (coarse->level() > 0) coarse = coarse->parent();
      std::array<Point<3>, 20> X;
      for (unsigned int v = 0; v < 8; ++v) X[v] = mesh.triangulation.get_vertices()[coarse->vertex_index(v)];
      for (unsigned int l = 0; l < 12; ++l)
        X[8 + l] = mesh.line_midpoint(coarse->line(l)->vertex_index(0), coarse->line(l)->vertex_index(1));
      cell->get_dof_indices(local);
      for (unsigned int i = 0; i < local.size(); ++i)
        {
          const auto [component, node] = geometry_fe.system_to_component_index(i);
          if (cell->level() == 0) // an unrefined cell's nodes are the mesh nodes
            {
              positions[local[i]] = X[node][component];
              continue;
            }
          const Point<3> p = coarse_coordinates(cell, reference[node]);
          double x = 0;
          for (unsigned int j = 0; j < 20; ++j) x += N.compute_value(j, p) * X[j][component];
          positions[local[i]] = x;
        }
    }
  map = std::make_unique<MappingFEField<3, 3, Vector<double>>>(geometry_dofs, positions);
}

void SolidModel::tabulate_node_dofs()
{
  // One pass over the cells: the (x, y, z) dofs at every vertex and, where the element has
  // line dofs, at every edge midpoint.
  for (const auto &cell : dofs.active_cell_iterators())
    {
      for (unsigned int v = 0; v < 8; ++v)
        dofs_at_node.try_emplace(MeshNode{true, cell->vertex_index(v), {0, 0}},
                                 std::vector<types::global_dof_index>{cell->vertex_dof_index(v, 0),
                                                                      cell->vertex_dof_index(v, 1),
                                                                      cell->vertex_dof_index(v, 2)});
      if (fe->n_dofs_per_line() > 0)
        for (unsigned int l = 0; l < 12; ++l)
          dofs_at_node.try_emplace(
            MeshNode{false, 0, ordered_edge(cell->line(l)->vertex_index(0), cell->line(l)->vertex_index(1))},
            std::vector<types::global_dof_index>{cell->line(l)->dof_index(0), cell->line(l)->dof_index(1),
                                                 cell->line(l)->dof_index(2)});
    }
}

std::vector<types::global_dof_index> SolidModel::node_dofs(const MeshNode &node) const
{
  const auto it = dofs_at_node.find(node);
  return it != dofs_at_node.end() ? it->second : std::vector<types::global_dof_index>();
}

std::vector<Point<3>> SolidModel::support_points() const
{
  // Every cell is present on every process (shared triangulation): map each cell's unit support
  // points through the 20-node geometry.
  std::vector<Point<3>> points(dofs.n_dofs());
  const Quadrature<3> nodes(fe->get_unit_support_points());
  FEValues<3> values(*map, *fe, nodes, update_quadrature_points);
  std::vector<types::global_dof_index> local(fe->n_dofs_per_cell());
  for (const auto &cell : dofs.active_cell_iterators())
    {
      values.reinit(cell);
      cell->get_dof_indices(local);
      for (unsigned int i = 0; i < local.size(); ++i) points[local[i]] = values.quadrature_point(i);
    }
  return points;
}

std::vector<unsigned int> SolidModel::dof_components() const
{
  // From the cell-local numbering.
  std::vector<unsigned int> component(dofs.n_dofs());
  std::vector<types::global_dof_index> local(fe->n_dofs_per_cell());
  for (const auto &cell : dofs.active_cell_iterators())
    {
      cell->get_dof_indices(local);
      for (unsigned int i = 0; i < local.size(); ++i) component[local[i]] = fe->system_to_component_index(i).first;
    }
  return component;
}

std::vector<types::global_dof_index> SolidModel::support_dofs(const SolidSupport &support,
                                                               const std::vector<Point<3>> &points,
                                                               const std::vector<unsigned int> &component) const
{
  std::vector<types::global_dof_index> held;
  if (support.plane_axis >= 0)
    {
      double size = 0;
      for (const auto &v : body.mesh->triangulation.get_vertices()) size = std::max(size, v.norm());
      for (types::global_dof_index i = 0; i < dofs.n_dofs(); ++i)
        if (std::abs(points[i][support.plane_axis] - support.plane_position) <= 1e-9 * std::max(size, 1.0) &&
            support.fixed[component[i]])
          held.push_back(i);
    }
  else
    for (const auto &node : body.mesh->node_sets.at(support.node_set))
      {
        const auto node_dof = node_dofs(node);
        for (unsigned int c = 0; c < node_dof.size(); ++c)
          if (support.fixed[c]) held.push_back(node_dof[c]);
      }
  return held;
}

void SolidModel::apply_supports()
{
  std::vector<Point<3>> points;
  std::vector<unsigned int> component;
  auto fix = [&](types::global_dof_index dof) {
    if (!supports.is_constrained(dof)) supports.add_line(dof);
  };
  types::boundary_id id = 1;
  std::map<std::string, types::boundary_id> set_ids;
  for (const auto &[name, nodes] : body.mesh->node_sets) set_ids[name] = id++;

  for (const auto &support : body.supports)
    {
      if (support.plane_axis >= 0 || level == 0)
        {
          if (support.plane_axis >= 0 && points.empty())
            {
              points = support_points();
              component = dof_components();
            }
          const auto held = support_dofs(support, points, component);
          if (held.empty() && support.plane_axis >= 0)
            throw InputError("Solid/Supports", "the plane in '" + support.text + "' contains no node of " +
                             body.mesh->source);
          for (const auto i : held) fix(i);
        }
      else
        {
          std::vector<bool> mask = {support.fixed[0], support.fixed[1], support.fixed[2]};
          const IndexSet on_faces =
            DoFTools::extract_boundary_dofs(dofs, ComponentMask(mask), {set_ids.at(support.node_set)});
          if (on_faces.n_elements() == 0)
            throw InputError("Solid/Supports", "node set '" + support.node_set + "' covers no whole face, so it "
                             "cannot be carried to refined meshes; use a plane support for 'converge'");
          for (const auto i : on_faces) fix(i);
        }
    }
  supports.close();
  if (constrained_assembly && !body.supports.empty()) refuse_unsupported_parts();
}

void SolidModel::refuse_unsupported_parts() const
{
  // Parts of the mesh that share no vertex: union-find over the vertices of every cell.
  std::vector<unsigned int> parent(tria.n_vertices());
  for (unsigned int v = 0; v < parent.size(); ++v) parent[v] = v;
  auto root = [&](unsigned int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto &cell : tria.active_cell_iterators())
    for (const auto v : cell->vertex_indices()) parent[root(cell->vertex_index(v))] = root(cell->vertex_index(0));

  // Per part: its cells, a point of it, and whether any of its dofs is supported.
  struct Part
  {
    unsigned int cells = 0;
    Point<3> centre;
    bool supported = false;
  };
  std::map<unsigned int, Part> parts;
  std::vector<types::global_dof_index> local(fe->n_dofs_per_cell());
  for (const auto &cell : dofs.active_cell_iterators())
    {
      Part &part = parts[root(cell->vertex_index(0))];
      ++part.cells;
      part.centre += cell->center();
      cell->get_dof_indices(local);
      for (const auto i : local) part.supported |= supports.is_constrained(i);
    }
  if (parts.size() < 2) return;
  for (const auto &[id, part] : parts)
    if (!part.supported)
      {
        const Point<3> c = part.centre / part.cells;
        std::ostringstream m;
        m << "the mesh of " << body.mesh->source << " has " << parts.size() << " parts that share no node, and "
          << "the part of " << part.cells << " cells around (" << c[0] << ", " << c[1] << ", " << c[2]
          << ") m has no support: it would float freely (zero or negative frequencies); support every part, "
             "join the parts, or remove the loose one";
        throw InputError("Solid/Supports", m.str());
      }
}

void SolidModel::cell_matrices(FEValues<3> &values, const DoFHandler<3>::active_cell_iterator &cell,
                               FullMatrix<double> &k_cell, FullMatrix<double> *m_cell) const
{
  const Material &m = body.material;
  const double mu = m.youngs_modulus / (2 * (1 + m.poisson_ratio));
  const double lambda = m.youngs_modulus * m.poisson_ratio / ((1 + m.poisson_ratio) * (1 - 2 * m.poisson_ratio));
  const unsigned int n = fe->n_dofs_per_cell();
  values.reinit(cell);
  k_cell = 0;
  if (m_cell) *m_cell = 0;
  // The element is primitive (each shape function has one non-zero component): tabulate that
  // component's value and gradient per quadrature point, then form the integrands.
  std::vector<unsigned int> component(n);
  for (unsigned int i = 0; i < n; ++i) component[i] = fe->system_to_component_index(i).first;
  std::vector<double> N(n);
  std::vector<Tensor<1, 3>> G(n);
  for (unsigned int q = 0; q < values.n_quadrature_points; ++q)
    {
      const double dx = values.JxW(q);
      for (unsigned int i = 0; i < n; ++i)
        {
          N[i] = values.shape_value(i, q);
          G[i] = values.shape_grad(i, q);
        }
      for (unsigned int i = 0; i < n; ++i)
        {
          const unsigned int ci = component[i];
          const Tensor<1, 3> &gi = G[i];
          for (unsigned int j = 0; j <= i; ++j)
            {
              const unsigned int cj = component[j];
              const Tensor<1, 3> &gj = G[j];
              // Isotropic elasticity (deal.II step-8): lambda div div + mu (grad + grad^T).
              double k = lambda * gi[ci] * gj[cj] + mu * gi[cj] * gj[ci];
              if (ci == cj)
                {
                  k += mu * (gi * gj);
                  if (m_cell) (*m_cell)(i, j) += m.density * N[i] * N[j] * dx;
                }
              k_cell(i, j) += k * dx;
            }
        }
    }
}

void SolidModel::assemble()
{
  AffineConstraints<double> none;
  none.close();
  const AffineConstraints<double> &applied = constrained_assembly ? supports : none;
  // The pattern of the rows this process writes (its own rows and those its cells touch) from
  // every cell: DoFTools::make_sparsity_pattern would visit only this process's cells, and miss
  // couplings of its rows through the neighbours' cells. Under MPI the pattern holds those rows
  // only (a pattern of every row would be the whole matrix's graph on every process, and Trilinos
  // would keep the rows it does not own as a second matrix for the values sent to their owners).
  {
    const IndexSet &owned = dofs.locally_owned_dofs();
    std::vector<types::global_dof_index> cell_dofs(fe->n_dofs_per_cell());
    IndexSet written; // empty: every row (one process)
    if (Utilities::MPI::n_mpi_processes(tria.get_communicator()) > 1)
      {
        written.set_size(dofs.n_dofs());
        std::vector<types::global_dof_index> rows;
        for (const auto &cell : dofs.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              cell->get_dof_indices(cell_dofs);
              rows.insert(rows.end(), cell_dofs.begin(), cell_dofs.end());
            }
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
        written.add_indices(rows.begin(), rows.end());
        written.add_indices(owned);
        written.compress();
      }
    DynamicSparsityPattern pattern(dofs.n_dofs(), dofs.n_dofs(), written);
    for (const auto &cell : dofs.active_cell_iterators())
      {
        cell->get_dof_indices(cell_dofs);
        applied.add_entries_local_to_global(cell_dofs, pattern, false);
      }
    stiffness.reinit(owned, owned, pattern, tria.get_communicator());
  }
  // M has K's pattern and shares K's graph (Epetra counts references): one copy of the column
  // indices instead of two, a third of a matrix.
  if (assemble_mass) mass.reinit(stiffness.trilinos_matrix(), false);
  base::release_free_heap();

  const QGauss<3> rule(body.gauss_points);
  FEValues<3> values(*map, *fe, rule, update_values | update_gradients | update_JxW_values);
  const unsigned int n = fe->n_dofs_per_cell();
  FullMatrix<double> k_cell(n, n), m_cell(n, n);
  std::vector<types::global_dof_index> local(n);
  for (const auto &cell : dofs.active_cell_iterators())
    {
      if (!cell->is_locally_owned()) continue;
      cell_matrices(values, cell, k_cell, assemble_mass ? &m_cell : nullptr);
      cell->get_dof_indices(local);
      add_symmetric_cell_matrices(k_cell, m_cell, local, applied, stiffness, mass);
    }
  finish_assembly(applied, stiffness, mass);
  base::release_free_heap();
  base::probe_memory("solid K and M assembled");
}

const SolidMassOperator &SolidModel::mass_operator() const
{
  if (!cell_mass)
    {
      std::vector<bool> held(dofs.n_dofs(), false);
      if (constrained_assembly)
        for (const auto &line : supports.get_lines())
          {
            // The assembled M drops the rows and columns of supported dofs; a support is a
            // homogeneous constraint u_i = 0 (no other kind is made here).
            Assert(line.entries.empty() && line.inhomogeneity == 0, ExcInternalError());
            held[line.index] = true;
          }
      cell_mass = std::make_unique<SolidMassOperator>(dofs, *map, QGauss<3>(body.gauss_points), body.material.density,
                                                      std::move(held));
    }
  return *cell_mass;
}

void SolidModel::release_stiffness()
{
  stiffness.clear();
  base::release_free_heap();
}

void SolidModel::release_matrices()
{
  stiffness.clear();
  mass.clear();
  base::release_free_heap();
}
} // namespace flextrack::fem
