// The cell-by-cell mass product of a solid (fem/solid_mass_operator.h) and the eigen solve that
// releases K and M before the factorisation (reduction::lowest_modes_releasing_matrices): both
// against the assembled matrices, which the solid tests check against CalculiX.
#include "steel_solid.h"

#include <fem/solid_model.h>
#include <reduction/modal_solver.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace flextrack;

namespace
{
/// A vector with entries of both signs and no pattern (deterministic).
dealii::Vector<double> test_vector(const unsigned int n)
{
  dealii::Vector<double> x(n);
  for (unsigned int i = 0; i < n; ++i) x[i] = std::sin(1.3 * i + 0.2) + 0.5 * std::cos(0.071 * i);
  return x;
}
} // namespace

TEST(SolidMassOperator, product_equals_the_assembled_supported_mass_matrix_for_every_element)
{
  // Curved hull edges (a distorted isoparametric map) and a clamp: y = M x against the assembled
  // M, whose frequencies match CalculiX's (solid tests). Tolerance 1e-13 of max |M x|: the two
  // sum the same cell contributions in another order (about 30 terms per entry).
  // Every element and Gauss rule the scene accepts (Solid/Element, Solid/Integration), and one
  // refined mesh (the `converge` path: cells mapped by their coarse ancestor's geometry).
  const std::shared_ptr<const fem::SolidMesh> mesh = fem::generate_cylinder(0.05, 0.6, 6);
  struct Case
  {
    fem::SolidElement element;
    unsigned int gauss, refinement;
  };
  for (const auto [element, gauss, refinement] :
       {Case{fem::SolidElement::hex20, 3, 0}, Case{fem::SolidElement::hex20, 2, 0}, Case{fem::SolidElement::hex8, 2, 0},
        Case{fem::SolidElement::hex8, 1, 0}, Case{fem::SolidElement::hex27, 3, 0}, Case{fem::SolidElement::hex27, 2, 0},
        Case{fem::SolidElement::hex20, 3, 1}})
    {
      fem::Solid body = test_support::steel_solid(mesh, "XMIN");
      body.element = element;
      body.gauss_points = gauss;
      const fem::SolidModel model(body, refinement);
      const auto x = test_vector(model.n_dofs());
      dealii::Vector<double> assembled(model.n_dofs()), cellwise(model.n_dofs());
      model.mass_matrix().vmult(assembled, x);
      model.mass_operator().vmult(x.begin(), cellwise.begin());
      double largest = 0, difference = 0;
      for (unsigned int i = 0; i < model.n_dofs(); ++i)
        {
          largest = std::max(largest, std::abs(assembled[i]));
          difference = std::max(difference, std::abs(assembled[i] - cellwise[i]));
          if (model.constraints().is_constrained(i)) { EXPECT_EQ(cellwise[i], 0.0) << "held dof " << i; }
        }
      std::cout << "  element " << static_cast<int>(element) << ", " << gauss << "^3 Gauss points, refinement "
                << refinement << ": max |M x| "
                << largest << " kg, largest difference " << difference / largest << " of it\n";
      EXPECT_LT(difference, 1e-13 * largest);
    }
}

TEST(SolidMassOperator, rigid_translation_carries_the_mass_of_a_box)
{
  // A free steel box 0.3 x 0.2 x 0.1 m (affine cells: the Gauss rule integrates N_a N_b
  // exactly): 1_x^T M 1_x = rho V = 7850 * 0.006 = 47.1 kg (closed form), to 1e-13.
  fem::Solid body = test_support::steel_solid(fem::generate_box(dealii::Point<3>(0.3, 0.2, 0.1), {{3, 2, 2}}), "XMIN");
  const fem::SolidModel model(body, 0, false); // supports listed, matrices of the free body
  std::vector<unsigned int> component(model.n_dofs());
  dealii::Vector<double> one_x(model.n_dofs()), y(model.n_dofs());
  const auto &fe = model.dof_handler().get_fe();
  std::vector<dealii::types::global_dof_index> local(fe.n_dofs_per_cell());
  for (const auto &cell : model.dof_handler().active_cell_iterators())
    {
      cell->get_dof_indices(local);
      for (unsigned int i = 0; i < local.size(); ++i)
        if (fe.system_to_component_index(i).first == 0) one_x[local[i]] = 1;
    }
  model.mass_operator().vmult(one_x.begin(), y.begin());
  const double mass = one_x * y;
  std::cout << "  1^T M 1 = " << mass << " kg, rho V = 47.1 kg\n";
  EXPECT_NEAR(mass, 47.1, 1e-13 * 47.1);
}

TEST(SolidModes, releasing_the_matrices_gives_the_modes_of_the_assembled_ones)
{
  // The cylinder cantilever of the solid tests (beam theory to 1 %): 6 modes from the assembled
  // K and M (lowest_modes) and from the path that frees them before the factorisation and
  // applies M cell by cell. Same factor, same Lanczos start: the frequencies agree to the
  // Lanczos tolerance (1e-12 relative, settings.tolerance), bound 1e-10. Afterwards the model
  // holds no matrices, and its mode shapes are mass-normalised with the assembled M of the
  // first model (phi^T M phi = 1 to 1e-10) and M-orthogonal to the reference shapes of the
  // other frequencies (|phi_k^T M phi_j| < 1e-8 where the frequencies differ by more than 1 %;
  // the cylinder's bending modes come in equal pairs, whose shapes may turn within the pair).
  const fem::Solid body = test_support::steel_solid(fem::generate_cylinder(0.025, 2.0, 40), "XMIN");
  reduction::ModalSettings settings;
  settings.n_modes = 6;
  const fem::SolidModel assembled(body);
  const auto reference = reduction::lowest_modes(assembled, settings);
  fem::SolidModel released(body);
  const auto modes = reduction::lowest_modes_releasing_matrices(released, settings);
  EXPECT_EQ(released.stiffness_matrix().m(), 0u);
  EXPECT_EQ(released.mass_matrix().m(), 0u);
  ASSERT_EQ(modes.eigenvalues.size(), reference.eigenvalues.size());
  for (std::size_t k = 0; k < modes.eigenvalues.size(); ++k)
    {
      const double d = std::abs(modes.eigenvalues[k] - reference.eigenvalues[k]) / reference.eigenvalues[k];
      std::cout << "  mode " << k + 1 << ": " << reduction::frequency_hz(modes.eigenvalues[k])
                << " Hz, relative difference of w^2 " << d << "\n";
      EXPECT_LT(d, 1e-10);
      dealii::Vector<double> Mphi(released.n_dofs());
      assembled.mass_matrix().vmult(Mphi, modes.shapes[k]);
      EXPECT_NEAR(modes.shapes[k] * Mphi, 1.0, 1e-10);
      for (std::size_t j = 0; j < reference.shapes.size(); ++j)
        if (std::abs(reference.eigenvalues[j] - modes.eigenvalues[k]) > 0.02 * modes.eigenvalues[k])
          {
            EXPECT_LT(std::abs(reference.shapes[j] * Mphi), 1e-8) << "modes " << k + 1 << ", " << j + 1;
          }
    }
}
