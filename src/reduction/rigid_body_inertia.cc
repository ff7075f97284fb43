#include <fem/curved_beam_model.h>
#include <fem/solid_model.h>
#include <reduction/rigid_body_inertia.h>

#include <deal.II/base/quadrature.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/trilinos_vector.h>

#include <array>

namespace flextrack::reduction
{
using namespace dealii;

namespace
{
/// Position and component of every dof, from the element's unit support points.
template <int dim>
void dof_positions(const DoFHandler<dim, 3> &dofs, const Mapping<dim, 3> &mapping, std::vector<Point<3>> &x,
                   std::vector<unsigned int> &component)
{
  const auto &fe = dofs.get_fe();
  x.resize(dofs.n_dofs());
  component.resize(dofs.n_dofs());
  const Quadrature<dim> nodes(fe.get_unit_support_points());
  FEValues<dim, 3> values(mapping, fe, nodes, update_quadrature_points);
  std::vector<types::global_dof_index> local(fe.n_dofs_per_cell());
  for (const auto &cell : dofs.active_cell_iterators())
    {
      values.reinit(cell);
      cell->get_dof_indices(local);
      for (unsigned int i = 0; i < local.size(); ++i)
        {
          x[local[i]] = values.quadrature_point(i);
          component[local[i]] = fe.system_to_component_index(i).first;
        }
    }
}

/// R^T M R for the six rigid-body motions, then m, c, J_c.
template <int dim>
RigidBodyInertia project(const TrilinosWrappers::SparseMatrix &M, const DoFHandler<dim, 3> &dofs,
                         const Mapping<dim, 3> &mapping)
{
  std::vector<Point<3>> x;
  std::vector<unsigned int> component;
  dof_positions(dofs, mapping, x, component);
  // Rotations about a point near the body (the mean node position), so that the parallel-axis
  // shift back to the centre of mass does not cancel digits.
  Point<3> reference;
  for (const auto &p : x) reference += p / static_cast<double>(x.size());
  for (auto &p : x) p -= reference;
  const IndexSet &owned = M.locally_owned_range_indices();
  std::array<TrilinosWrappers::MPI::Vector, 6> r, Mr;
  for (unsigned int k = 0; k < 6; ++k)
    {
      r[k].reinit(owned, M.get_mpi_communicator());
      Mr[k].reinit(owned, M.get_mpi_communicator());
      for (const auto i : owned)
        {
          const unsigned int c = component[i];
          if (c < 3) // a displacement: e_k, or (e_{k-3} x x)_c
            r[k][i] = k < 3 ? (c == k) : cross_product_3d(Tensor<1, 3>(Point<3>::unit_vector(k - 3)), x[i])[c];
          else // a section rotation (beams): 0, or e_{k-3}
            r[k][i] = k >= 3 && c - 3 == k - 3;
        }
      r[k].compress(VectorOperation::insert);
      M.vmult(Mr[k], r[k]);
    }
  double P[6][6];
  for (unsigned int a = 0; a < 6; ++a)
    for (unsigned int b = 0; b < 6; ++b) P[a][b] = r[a] * Mr[b];

  RigidBodyInertia result;
  result.mass = P[0][0];
  // P[i][3 + j] = m (e_j x c)_i: (e_y x c)_z = -c_x, (e_z x c)_x = -c_y, (e_x x c)_y = -c_z.
  const double m = result.mass;
  const Point<3> c(-P[2][4] / m, -P[0][5] / m, -P[1][3] / m); // relative to the reference
  result.centre_of_mass = reference + c;
  // P[3 + i][3 + j] = J about the reference; parallel axes: J_c = J_ref - m (|c|^2 1 - c c^T).
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j)
      result.inertia_about_centre[i][j] = P[3 + i][3 + j] - m * ((i == j ? c.square() : 0.0) - c[i] * c[j]);
  return result;
}
} // namespace

RigidBodyInertia rigid_body_inertia(const fem::Solid &solid)
{
  fem::Solid free_body = solid;
  free_body.supports.clear();
  const fem::SolidModel model(free_body);
  return project<3>(model.mass_matrix(), model.dof_handler(), model.mapping());
}

RigidBodyInertia rigid_body_inertia(const fem::Arm &arm)
{
  fem::Arm free_arm = arm;
  free_arm.supports = {{0.0, fem::SupportKind::free}, {arm.curve->length(), fem::SupportKind::free}};
  const fem::CurvedBeamModel model(free_arm);
  return project<1>(model.mass_matrix(), model.dof_handler(), model.mapping());
}
} // namespace flextrack::reduction
