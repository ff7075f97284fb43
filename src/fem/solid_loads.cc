// Static loads of a solid (issue 12): node set forces and moments spread by the consistent nodal
// weights of the set's boundary faces, gravity as a body force, the resultant of nodal forces,
// and the mean displacement and best-fit rotation of a node set. The
// isoparametric elements represent rigid motions exactly, so the resultant of a nodal load
// vector equals that of the distributed load it stands for, and reactions balance loads to
// round-off.
#include <base/input_error.h>
#include <fem/solid_loads.h>
#include <fem/solid_model.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>

#include <deal.II/base/symmetric_tensor.h>

#include <set>

namespace flextrack::fem
{
using namespace dealii;

namespace
{
/// Boundary faces (cell, face number) whose four corners all belong to @p nodes.
template <typename Dofs>
std::vector<std::pair<typename Dofs::active_cell_iterator, unsigned int>> faces_of(const Dofs &dofs,
                                                                                   const std::vector<MeshNode> &nodes)
{
  const std::set<MeshNode> set(nodes.begin(), nodes.end());
  std::vector<std::pair<typename Dofs::active_cell_iterator, unsigned int>> faces;
  for (const auto &cell : dofs.active_cell_iterators())
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary())
        {
          bool all = true;
          for (unsigned int v = 0; v < 4; ++v) all &= set.count(MeshNode{true, cell->face(f)->vertex_index(v), {0, 0}}) > 0;
          if (all) faces.emplace_back(cell, f);
        }
  return faces;
}
/// sum over @p points (with weights) of |r|^2 1 - r r^T, r = x - c: the area (or point) inertia
/// tensor about c.
Tensor<2, 3> inertia_about(const std::vector<std::pair<Point<3>, double>> &points, const Point<3> &c)
{
  Tensor<2, 3> J;
  for (const auto &[x, w] : points)
    {
      const Tensor<1, 3> r = x - c;
      J += w * (r * r * unit_symmetric_tensor<3>() - outer_product(r, r));
    }
  return J;
}

/// Weighted centroid of @p points.
Point<3> centroid(const std::vector<std::pair<Point<3>, double>> &points)
{
  Point<3> c;
  double total = 0;
  for (const auto &[x, w] : points)
    {
      c += w * x;
      total += w;
    }
  return c / total;
}
} // namespace

Vector<double> SolidModel::load_vector(const LoadCase &load_case) const
{
  Assert(level == 0, ExcMessage("static loads on the unrefined mesh only"));
  Vector<double> f(dofs.n_dofs());
  const unsigned int n = fe->n_dofs_per_cell();
  std::vector<types::global_dof_index> local(n);
  for (const auto &load : load_case.node_set_forces)
    {
      const auto &nodes = body.mesh->node_sets.at(load.node_set);
      const auto faces = faces_of(dofs, nodes);
      if (faces.empty())
        {
          // No whole face (a point, an edge): equal shares per node that carries dofs.
          std::vector<std::vector<types::global_dof_index>> at;
          for (const auto &node : nodes)
            if (auto d = node_dofs(node); !d.empty()) at.push_back(d);
          for (const auto &d : at)
            for (unsigned int c = 0; c < 3; ++c) f[d[c]] += load.force[c] / at.size();
          continue;
        }
      // A uniform traction t = F / area: f_i = int_faces N_i t dA.
      const QGauss<2> rule(body.gauss_points);
      FEFaceValues<3> values(*map, *fe, rule, update_values | update_JxW_values);
      double area = 0;
      for (const auto &[cell, face] : faces)
        {
          values.reinit(cell, face);
          for (unsigned int q = 0; q < rule.size(); ++q) area += values.JxW(q);
        }
      const Tensor<1, 3> traction = load.force / area;
      for (const auto &[cell, face] : faces)
        {
          values.reinit(cell, face);
          cell->get_dof_indices(local);
          for (unsigned int i = 0; i < n; ++i)
            {
              const unsigned int c = fe->system_to_component_index(i).first;
              for (unsigned int q = 0; q < rule.size(); ++q) f[local[i]] += traction[c] * values.shape_value(i, q) * values.JxW(q);
            }
        }
    }
  for (const auto &load : load_case.node_set_moments)
    {
      const auto &nodes = body.mesh->node_sets.at(load.node_set);
      const auto faces = faces_of(dofs, nodes);
      if (faces.empty())
        {
          // No whole face: nodal forces lambda x r_i, J summed over the nodes.
          const auto points = support_points();
          std::vector<std::vector<types::global_dof_index>> at;
          std::vector<std::pair<Point<3>, double>> x;
          for (const auto &node : nodes)
            if (auto d = node_dofs(node); !d.empty())
              {
                at.push_back(d);
                x.emplace_back(points[d[0]], 1.0);
              }
          const Point<3> c = centroid(x);
          const Tensor<1, 3> lambda = invert(inertia_about(x, c)) * load.moment;
          for (std::size_t k = 0; k < at.size(); ++k)
            {
              const Tensor<1, 3> F = cross_product_3d(lambda, x[k].first - c);
              for (unsigned int d = 0; d < 3; ++d) f[at[k][d]] += F[d];
            }
          continue;
        }
      // t(r) = lambda x r over the faces, J lambda = M: f_i = int_faces N_i t dA.
      const QGauss<2> rule(body.gauss_points);
      FEFaceValues<3> values(*map, *fe, rule, update_values | update_JxW_values | update_quadrature_points);
      std::vector<std::pair<Point<3>, double>> area_points;
      for (const auto &[cell, face] : faces)
        {
          values.reinit(cell, face);
          for (unsigned int q = 0; q < rule.size(); ++q) area_points.emplace_back(values.quadrature_point(q), values.JxW(q));
        }
      const Point<3> c = centroid(area_points);
      const Tensor<1, 3> lambda = invert(inertia_about(area_points, c)) * load.moment;
      for (const auto &[cell, face] : faces)
        {
          values.reinit(cell, face);
          cell->get_dof_indices(local);
          for (unsigned int q = 0; q < rule.size(); ++q)
            {
              const Tensor<1, 3> t = cross_product_3d(lambda, values.quadrature_point(q) - c);
              for (unsigned int i = 0; i < n; ++i)
                f[local[i]] += t[fe->system_to_component_index(i).first] * values.shape_value(i, q) * values.JxW(q);
            }
        }
    }
  for (const auto &load : load_case.node_forces)
    {
      // Nodes that carry dofs: all of a hex20 or hex27 mesh, the corners of a hex8 one (the
      // mid-side nodes of the 20-node geometry carry none there).
      unsigned int loaded = 0;
      for (const auto &node : body.mesh->node_sets.at(load.node_set))
        if (const auto d = node_dofs(node); !d.empty())
          {
            for (unsigned int c = 0; c < 3; ++c) f[d[c]] += load.force[c];
            ++loaded;
          }
      if (loaded == 0)
        throw InputError("Load case " + load_case.name + "/Node forces",
                         "no node of set '" + load.node_set + "' carries degrees of freedom with this element (hex8: "
                         "corner nodes only); allowed: a set with corner nodes, or 'Node set forces'");
    }
  for (const auto &load : load_case.pressures)
    {
      const auto faces = faces_of(dofs, body.mesh->node_sets.at(load.node_set));
      if (faces.empty())
        throw InputError("Load case " + load_case.name + "/Pressures",
                         "node set '" + load.node_set + "' holds no whole boundary face (a face whose corners all "
                         "belong to the set), so a pressure has nothing to act on; allowed: a set of boundary faces, "
                         "or 'Node set forces' for points and edges");
      // t = -p n on the curved faces (n outward, from the 20-node map): f_i = int_faces N_i t dA.
      const QGauss<2> rule(body.gauss_points);
      FEFaceValues<3> values(*map, *fe, rule, update_values | update_JxW_values | update_normal_vectors);
      for (const auto &[cell, face] : faces)
        {
          values.reinit(cell, face);
          cell->get_dof_indices(local);
          for (unsigned int q = 0; q < rule.size(); ++q)
            {
              const Tensor<1, 3> t = -load.pressure * values.normal_vector(q);
              for (unsigned int i = 0; i < n; ++i)
                f[local[i]] += t[fe->system_to_component_index(i).first] * values.shape_value(i, q) * values.JxW(q);
            }
        }
    }
  if (load_case.gravity.norm() > 0)
    {
      const QGauss<3> rule(body.gauss_points);
      FEValues<3> values(*map, *fe, rule, update_values | update_JxW_values);
      const Tensor<1, 3> weight = body.material.density * load_case.gravity;
      for (const auto &cell : dofs.active_cell_iterators())
        {
          values.reinit(cell);
          cell->get_dof_indices(local);
          for (unsigned int i = 0; i < n; ++i)
            {
              const unsigned int c = fe->system_to_component_index(i).first;
              for (unsigned int q = 0; q < rule.size(); ++q) f[local[i]] += weight[c] * values.shape_value(i, q) * values.JxW(q);
            }
        }
    }
  return f;
}

Vector<double> SolidModel::support_displacements(const LoadCase &load_case) const
{
  Assert(level == 0, ExcMessage("static loads on the unrefined mesh only"));
  Vector<double> g(dofs.n_dofs());
  if (load_case.support_displacements.empty()) return g;
  const auto points = support_points();
  const auto component = dof_components();
  // Which item set each dof: two items that share nodes must agree there (a listed support
  // sharing nodes with one that is not listed moves them: the listed value applies).
  std::vector<int> set_by(dofs.n_dofs(), -1);
  const auto prescribe = [&](const types::global_dof_index i, const unsigned int item, const double value) {
    if (set_by[i] >= 0 && g[i] != value)
      throw InputError("Load case " + load_case.name + "/Support displacements",
                       "'" + load_case.support_displacements[set_by[i]].label + "' and '" +
                         load_case.support_displacements[item].label +
                         "' share nodes but prescribe different displacements there; allowed: equal values on "
                         "shared nodes");
    g[i] = value;
    set_by[i] = static_cast<int>(item);
  };
  for (unsigned int item = 0; item < load_case.support_displacements.size(); ++item)
    {
      const auto &d = load_case.support_displacements[item];
      for (const unsigned int k : d.supports)
        for (const auto i : support_dofs(body.supports.at(k), points, component)) prescribe(i, item, d.value[component[i]]);
    }
  return g;
}

std::vector<long double> SolidModel::internal_forces(const std::vector<long double> &u) const
{
  const auto points = support_points();
  const auto component = dof_components();
  const QGauss<3> rule(body.gauss_points);
  FEValues<3> values(*map, *fe, rule, update_values | update_gradients | update_JxW_values);
  const unsigned int n = fe->n_dofs_per_cell();
  FullMatrix<double> k_cell(n, n);
  std::vector<types::global_dof_index> local(n);
  std::vector<long double> g(dofs.n_dofs(), 0.0L), d(n);
  for (const auto &cell : dofs.active_cell_iterators())
    {
      cell_matrices(values, cell, k_cell, nullptr);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < i; ++j) k_cell(j, i) = k_cell(i, j);
      cell->get_dof_indices(local);
      // The cell's best-fit rigid motion t + omega x (x - c) (least squares over its nodes; any
      // rigid motion would do, K_e annihilates it, the fit leaves the smallest rest), evaluated
      // in long double from its double parameters: exactly rigid to 1e-19, so that its forces
      // are K_e's round-off on rigid motions times a small rest only.
      std::vector<std::pair<Point<3>, double>> x;
      Tensor<1, 3> t;
      for (unsigned int i = 0; i < n; ++i)
        if (component[local[i]] == 0) x.emplace_back(points[local[i]], 1.0);
      for (unsigned int i = 0; i < n; ++i) t[component[local[i]]] += static_cast<double>(u[local[i]]) / x.size();
      const Point<3> c = centroid(x);
      Tensor<1, 3> moment;
      for (unsigned int i = 0; i < n; ++i)
        {
          Tensor<1, 3> ui;
          ui[component[local[i]]] = static_cast<double>(u[local[i]]) - t[component[local[i]]];
          moment += cross_product_3d(points[local[i]] - c, ui);
        }
      const Tensor<1, 3> omega = invert(inertia_about(x, c)) * moment;
      for (unsigned int i = 0; i < n; ++i)
        {
          const unsigned int ci = component[local[i]], a = (ci + 1) % 3, b = (ci + 2) % 3;
          const long double ra = static_cast<long double>(points[local[i]][a]) - c[a];
          const long double rb = static_cast<long double>(points[local[i]][b]) - c[b];
          // (omega x r)_ci = omega_a r_b - omega_b r_a for (ci, a, b) cyclic.
          const long double rigid = static_cast<long double>(t[ci]) + static_cast<long double>(omega[a]) * rb -
                                    static_cast<long double>(omega[b]) * ra;
          d[i] = u[local[i]] - rigid;
        }
      for (unsigned int i = 0; i < n; ++i)
        {
          long double sum = 0;
          for (unsigned int j = 0; j < n; ++j) sum += static_cast<long double>(k_cell(i, j)) * d[j];
          g[local[i]] += sum;
        }
    }
  return g;
}

std::vector<Vector<double>> SolidModel::rigid_body_modes() const
{
  const auto points = support_points();
  const auto component = dof_components();
  std::vector<Vector<double>> modes(6, Vector<double>(dofs.n_dofs()));
  for (types::global_dof_index i = 0; i < dofs.n_dofs(); ++i)
    {
      const unsigned int c = component[i];
      modes[c][i] = 1;
      for (unsigned int d = 0; d < 3; ++d)
        {
          Tensor<1, 3> axis;
          axis[d] = 1;
          modes[3 + d][i] = cross_product_3d(axis, Tensor<1, 3>(points[i]))[c];
        }
    }
  return modes;
}

Resultant SolidModel::nodal_resultant(const Vector<double> &r) const
{
  const auto points = support_points();
  const auto component = dof_components();
  Resultant total;
  for (types::global_dof_index i = 0; i < dofs.n_dofs(); ++i)
    {
      Tensor<1, 3> F;
      F[component[i]] = r[i];
      total.force += F;
      total.moment += cross_product_3d(Tensor<1, 3>(points[i]), F);
    }
  return total;
}

Tensor<1, 3> SolidModel::mean_displacement(const std::string &set, const Vector<double> &u) const
{
  Tensor<1, 3> sum;
  unsigned int count = 0;
  for (const auto &node : body.mesh->node_sets.at(set))
    if (const auto d = node_dofs(node); !d.empty())
      {
        for (unsigned int c = 0; c < 3; ++c) sum[c] += u[d[c]];
        ++count;
      }
  return count ? sum / count : sum;
}

Tensor<1, 3> mean_rotation(const SolidModel &model, const Solid &solid, const std::string &set, const Vector<double> &u)
{
  const auto points = model.support_points();
  std::vector<std::pair<Point<3>, double>> x;
  std::vector<Tensor<1, 3>> v;
  for (const auto &node : solid.mesh->node_sets.at(set))
    if (const auto d = model.node_dofs(node); !d.empty())
      {
        x.emplace_back(points[d[0]], 1.0);
        v.push_back(Tensor<1, 3>({u[d[0]], u[d[1]], u[d[2]]}));
      }
  if (x.size() < 3) return Tensor<1, 3>();
  const Point<3> c = centroid(x);
  Tensor<1, 3> mean, moment;
  for (const auto &w : v) mean += w / static_cast<double>(v.size());
  for (std::size_t k = 0; k < x.size(); ++k) moment += cross_product_3d(x[k].first - c, v[k] - mean);
  return invert(inertia_about(x, c)) * moment;
}
} // namespace flextrack::fem
