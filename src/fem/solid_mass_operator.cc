#include <fem/solid_mass_operator.h>

#include <deal.II/fe/fe_values.h>

#include <algorithm>
#include <stdexcept>

namespace flextrack::fem
{
using namespace dealii;

SolidMassOperator::SolidMassOperator(const DoFHandler<3> &dofs, const Mapping<3> &mapping, const Quadrature<3> &rule,
                                     const double rho, std::vector<bool> held_dofs)
  : n_dofs(dofs.n_dofs()), held(std::move(held_dofs))
{
  const FiniteElement<3> &fe = dofs.get_fe();
  // Three copies of one scalar element (FESystem(FE_Q or FE_Serendipity, 3)): only then is the
  // cell's mass block one scalar matrix per component.
  if (fe.n_components() != 3 || fe.n_base_elements() != 1 || fe.element_multiplicity(0) != 3 || !fe.is_primitive())
    throw std::logic_error("SolidMassOperator: the element must be three copies of one scalar element");
  n_scalar = fe.n_dofs_per_cell() / 3;
  if (held.empty()) held.assign(n_dofs, false);
  if (held.size() != n_dofs) throw std::logic_error("SolidMassOperator: one 'held' flag per dof expected");
  // local[a * 3 + c]: the cell dof of scalar function a in component c.
  std::vector<unsigned int> local(fe.n_dofs_per_cell());
  for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
    {
      const auto [component, scalar] = fe.system_to_component_index(i);
      local[scalar * 3 + component] = i;
    }
  const std::size_t n_cells = dofs.get_triangulation().n_active_cells();
  const std::size_t packed = n_scalar * (n_scalar + 1) / 2;
  cell_dofs.reserve(n_cells * fe.n_dofs_per_cell());
  cell_masses.reserve(n_cells * packed);
  FEValues<3> values(mapping, fe, rule, update_values | update_JxW_values);
  std::vector<types::global_dof_index> indices(fe.n_dofs_per_cell());
  std::vector<double> N(n_scalar);
  std::vector<double> m(packed);
  // Every active cell, owned or not: under MPI each process keeps the whole mesh (a shared
  // triangulation), and the product is then the complete one on every process.
  for (const auto &cell : dofs.active_cell_iterators())
    {
      values.reinit(cell);
      cell->get_dof_indices(indices);
      for (const unsigned int i : local) cell_dofs.push_back(indices[i]);
      std::fill(m.begin(), m.end(), 0.0);
      for (unsigned int q = 0; q < rule.size(); ++q)
        {
          const double w = rho * values.JxW(q);
          for (unsigned int a = 0; a < n_scalar; ++a) N[a] = values.shape_value(local[a * 3], q);
          std::size_t e = 0;
          for (unsigned int a = 0; a < n_scalar; ++a)
            for (unsigned int b = 0; b <= a; ++b) m[e++] += w * N[a] * N[b];
        }
      cell_masses.insert(cell_masses.end(), m.begin(), m.end());
    }
}

void SolidMassOperator::vmult(const double *x, double *y) const
{
  std::fill(y, y + n_dofs, 0.0);
  const std::size_t packed = n_scalar * (n_scalar + 1) / 2, n_cells = cell_masses.size() / packed;
  std::vector<double> xs(3 * n_scalar), ys(3 * n_scalar);
  for (std::size_t k = 0; k < n_cells; ++k)
    {
      const types::global_dof_index *dof = &cell_dofs[k * 3 * n_scalar];
      for (unsigned int i = 0; i < 3 * n_scalar; ++i) xs[i] = held[dof[i]] ? 0.0 : x[dof[i]];
      std::fill(ys.begin(), ys.end(), 0.0);
      const double *m = &cell_masses[k * packed];
      for (unsigned int a = 0; a < n_scalar; ++a)
        {
          for (unsigned int b = 0; b < a; ++b, ++m)
            for (unsigned int c = 0; c < 3; ++c)
              {
                ys[3 * a + c] += *m * xs[3 * b + c];
                ys[3 * b + c] += *m * xs[3 * a + c];
              }
          for (unsigned int c = 0; c < 3; ++c) ys[3 * a + c] += *m * xs[3 * a + c];
          ++m;
        }
      for (unsigned int i = 0; i < 3 * n_scalar; ++i) y[dof[i]] += ys[i];
    }
  for (std::size_t i = 0; i < n_dofs; ++i)
    if (held[i]) y[i] = 0.0;
}

std::size_t SolidMassOperator::memory_consumption() const
{
  return cell_dofs.capacity() * sizeof(types::global_dof_index) + cell_masses.capacity() * sizeof(double) +
         held.capacity() / 8;
}
} // namespace flextrack::fem
