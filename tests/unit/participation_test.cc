// Modal participation factors and effective masses (issue 12 item 4) of a uniform cantilever
// against Euler-Bernoulli (REFERENCES.md section 8).
#include <fem/curved_beam_model.h>
#include <io/arm_scene.h>
#include <reduction/modal_participation.h>
#include <reduction/modal_solver.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/component_mask.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace flextrack;

TEST(ModalParticipation, cantilever_effective_masses_match_euler_bernoulli_and_sum_to_the_moving_mass)
{
  // Slender steel cantilever along x, L = 3 m, circle d = 0.01 m (L/d = 300), 64 cubic elements,
  // 24 modes (bending in y and z come in pairs). Euler-Bernoulli effective mass of a uniform
  // cantilever as a fraction of its mass rho A L (REFERENCES.md section 8): mode 1 0.6131,
  // mode 2 0.1883, mode 3 0.0647. Tolerance 1e-3 absolute (shear and rotary inertia at
  // L/d = 300 change them by about 1e-5).
  dealii::ParameterHandler prm;
  io::declare_arm_scene(prm);
  const auto scene = io::read_arm_scene_from_string(
    "subsection Arm\n subsection Curve\n  set Kind = line\n  subsection Line\n   set End point = 3, 0, 0\n  end\n end\n"
    " subsection Cross section\n  set Shape = circle\n  set Diameter = 0.01\n end\n"
    " subsection Mesh\n  set Number of elements = 64\n  set Element degree = 3\n end\nend\n"
    "subsection Modal analysis\n set Number of modes = 24\nend\n",
    prm);
  const fem::CurvedBeamModel model(scene.arm);
  const auto modes = reduction::lowest_modes(model, scene.modal);
  std::vector<unsigned int> component(model.n_dofs());
  for (unsigned int c = 0; c < 6; ++c)
    {
      std::vector<bool> mask(6, false);
      mask[c] = true;
      for (const auto i : dealii::DoFTools::extract_dofs(model.dof_handler(), dealii::ComponentMask(mask))) component[i] = c;
    }
  const auto p = reduction::modal_participation(modes.shapes, model.mass_matrix(), component);
  const double mass = 7850 * M_PI * 0.01 * 0.01 / 4 * 3;
  // Bending modes in y: the modes whose effective mass is mostly along y, in ascending order.
  std::vector<double> fraction_y;
  double sum_y = 0;
  for (const auto &m : p.effective_mass)
    {
      sum_y += m[1];
      if (m[1] > m[0] && m[1] > m[2]) fraction_y.push_back(m[1] / mass);
    }
  ASSERT_GE(fraction_y.size(), 3u);
  const double reference[] = {0.6131, 0.1883, 0.0647};
  for (unsigned int k = 0; k < 3; ++k)
    {
      std::cout << "  bending mode " << k + 1 << " in y: " << fraction_y[k] << " of rho A L (Euler-Bernoulli "
                << reference[k] << ")\n";
      EXPECT_NEAR(fraction_y[k], reference[k], 1e-3);
    }
  // The moving mass (supported dofs have zero rows in M) is rho A L up to the clamp node's share.
  std::cout << "  moving mass y " << p.total_mass[1] << " kg of rho A L = " << mass << " kg; 24 modes carry "
            << sum_y / p.total_mass[1] << " of it\n";
  EXPECT_NEAR(p.total_mass[1] / mass, 1, 0.01);
  EXPECT_GT(sum_y / p.total_mass[1], 0.95);
  EXPECT_LE(sum_y / p.total_mass[1], 1 + 1e-9);
}
