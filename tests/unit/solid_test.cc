// 3D bodies with 20-node hexahedra against CalculiX (same mesh) and beam theory.
#include "solid_mesh_writer.h"
#include "steel_solid.h"

#include <fem/solid_model.h>
#include <base/input_error.h>
#include <reduction/sparse_factorization.h>
#include <reduction/modal_solver.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>

using namespace flextrack;
using dealii::Point;

namespace
{
/// x = A^{-1} b through the project's sparse direct factorisation (KLU; A need not be definite).
dealii::Vector<double> solve_direct(const dealii::TrilinosWrappers::SparseMatrix &A, const dealii::Vector<double> &b)
{
  // A = K - sigma M with sigma = 0: A itself.
  const reduction::SparseFactorization factor(A, A, 0.0, "klu");
  dealii::Vector<double> x(b.size());
  factor.solve(b.begin(), x.begin());
  return x;
}

/// K u = 0 with u_i = values_i for i in @p prescribed: those rows become u_i = value_i.
dealii::Vector<double> solve_with_prescribed_values(const dealii::TrilinosWrappers::SparseMatrix &K,
                                                    const dealii::IndexSet &prescribed, const dealii::Vector<double> &values)
{
  dealii::TrilinosWrappers::SparseMatrix A;
  A.copy_from(K);
  dealii::Vector<double> rhs(K.m());
  for (const auto i : prescribed)
    {
      A.clear_row(i, 1.0);
      rhs[i] = values[i];
    }
  return solve_direct(A, rhs);
}

std::string work_directory(const std::string &name)
{
  const std::string dir = std::filesystem::temp_directory_path().string() + "/flextrack_test_" + name;
  std::filesystem::create_directories(dir);
  return dir;
}

/// Frequencies of FlexTrack and CalculiX on the same .inp file; prints both.
void compare_with_calculix(const std::string &dir, const std::string &job, unsigned int n_modes)
{
  const auto ccx = test_support::run_calculix(dir, job);
  ASSERT_EQ(ccx.size(), n_modes) << "CalculiX (ccx, Debian package calculix-ccx) did not run; see " << dir << "/"
                                 << job << ".ccx.log";
  const fem::Solid body = test_support::steel_solid(fem::read_abaqus_mesh(dir + "/" + job + ".inp", "test"));
  const fem::SolidModel model(body);
  reduction::ModalSettings settings;
  settings.n_modes = n_modes;
  const auto f = reduction::lowest_modes(model, settings).frequencies_hz();
  std::cout << "  mode   FlexTrack [Hz]     CalculiX [Hz]   rel. diff.   (" << model.n_dofs() << " dofs)\n";
  for (unsigned int k = 0; k < n_modes; ++k)
    {
      const double d = std::abs(f[k] - ccx[k]) / ccx[k];
      std::cout << "  " << std::setw(4) << k + 1 << std::setw(17) << std::setprecision(10) << f[k] << std::setw(18)
                << ccx[k] << std::setw(13) << std::setprecision(2) << std::scientific << d << std::defaultfloat << "\n";
      // Same mesh, same element (C3D20, 3x3x3 Gauss, consistent mass): agreement to 1e-5 (issue 3),
      // limited by the 7 digits CalculiX prints.
      EXPECT_LT(d, 1e-5) << "mode " << k + 1;
    }
}
} // namespace

TEST(Solid, hex20_frequencies_match_calculix_on_a_tapered_bent_cantilever)
{
  // A cantilever 1 m long, tapering from 0.2 x 0.16 m to 0.1 x 0.08 m, its axis bent upwards
  // in a parabola and its sections sheared along x: every element is distorted, edges curved.
  // (CalculiX 2.20 refuses a variant with an extra y-shear 0.05 x z as "nonpositive jacobian",
  // although the Jacobian is positive at all 27 Gauss points of every element.)
  const std::string dir = work_directory("tapered");
  test_support::write_hex20_inp(dir + "/tapered.inp", 6, 2, 2, [](double xi, double eta, double zeta) {
    const double x = xi, taper = 1 - 0.5 * xi;
    return Point<3>(x + 0.03 * (eta - 0.5), 0.2 * taper * (eta - 0.5), 0.16 * taper * (zeta - 0.5) + 0.15 * xi * xi);
  });
  compare_with_calculix(dir, "tapered", 10);
}

TEST(Solid, curved_edge_mesh_from_file_matches_calculix)
{
  // meshes/curved_bracket.inp: a quarter annulus (radii 0.2 and 0.3 m, 0.05 m thick) whose
  // mid-side nodes lie on the arcs, clamped at one end (node set FIX).
  const std::string dir = work_directory("bracket");
  std::filesystem::copy_file(FLEXTRACK_SOURCE_DIR "/meshes/curved_bracket.inp", dir + "/curved_bracket.inp",
                             std::filesystem::copy_options::overwrite_existing);
  compare_with_calculix(dir, "curved_bracket", 10);
}

TEST(Solid, patch_test_reproduces_a_linear_field_on_a_distorted_mesh)
{
  // Patch test (Irons; Zienkiewicz & Taylor vol. 1, ch. 9): prescribe u = a + B x on the
  // boundary nodes of a distorted 20-node mesh (interior corner and mid-side nodes moved,
  // curved edges); the solution at every node must be u = a + B x exactly (1e-10 relative).
  const std::string dir = work_directory("patch");
  test_support::write_hex20_inp(dir + "/patch.inp", 3, 3, 3, [](double x, double y, double z) {
    const double bump = std::sin(M_PI * x) * std::sin(M_PI * y) * std::sin(M_PI * z);
    return Point<3>(x + 0.08 * bump + 0.05 * y * y, y - 0.06 * bump + 0.04 * z * x, z + 0.07 * bump);
  });
  const auto mesh = std::shared_ptr<const fem::SolidMesh>(fem::read_abaqus_mesh(dir + "/patch.inp", "test"));
  fem::Solid body = test_support::steel_solid(mesh);
  body.supports.clear();
  const fem::SolidModel model(body);
  const auto x = model.support_points();
  auto exact = [](const Point<3> &p, unsigned int c) {
    const double a[3] = {0.001, -0.002, 0.0005};
    const double B[3][3] = {{1e-3, 2e-4, -3e-4}, {-1e-4, 5e-4, 2e-4}, {3e-4, -2e-4, -4e-4}};
    return a[c] + B[c][0] * p[0] + B[c][1] * p[1] + B[c][2] * p[2];
  };
  // Boundary dofs: support points on the boundary of the unit cube's image (the faces are
  // the images of xi, eta, zeta in {0, 1}: bump = 0 there, so they are the planes' images).
  const auto boundary = dealii::DoFTools::extract_boundary_dofs(model.dof_handler());
  std::vector<unsigned int> component(model.n_dofs());
  {
    std::vector<dealii::types::global_dof_index> local(model.dof_handler().get_fe().n_dofs_per_cell());
    for (const auto &cell : model.dof_handler().active_cell_iterators())
      {
        cell->get_dof_indices(local);
        for (unsigned int i = 0; i < local.size(); ++i)
          component[local[i]] = model.dof_handler().get_fe().system_to_component_index(i).first;
      }
  }
  dealii::Vector<double> prescribed(model.n_dofs());
  for (const auto i : boundary) prescribed[i] = exact(x[i], component[i]);
  const dealii::Vector<double> u = solve_with_prescribed_values(model.stiffness_matrix(), boundary, prescribed);
  double worst = 0, scale = 0;
  for (unsigned int i = 0; i < model.n_dofs(); ++i)
    {
      worst = std::max(worst, std::abs(u[i] - exact(x[i], component[i])));
      scale = std::max(scale, std::abs(exact(x[i], component[i])));
    }
  std::cout << "  largest nodal error " << worst << " m, field size " << scale << " m\n";
  EXPECT_LT(worst, 1e-10 * scale);
}

TEST(Solid, slender_block_tip_deflection_and_first_frequency_match_beam_theory)
{
  // Steel block L = 2 m, b = h = 0.1 m (L/h = 20), 40 x 2 x 2 hex20 cells, clamped at x = 0
  // (all displacements of that face fixed), load P = 1 kN along -z spread uniformly over the
  // end face. Timoshenko beam (Timoshenko & Gere, Mechanics of Materials; Cowper's k for a
  // rectangle, k = 10 (1 + nu) / (12 + 11 nu)):
  //   tip deflection = P L^3 / (3 E I) + P L / (k G A).
  // First bending frequency, Euler-Bernoulli: (1.875104)^2 sqrt(E I / (rho A L^4)) / (2 pi);
  // shear and rotary inertia lower it by ~0.3 % at L/h = 20. Tolerance 1 % for both (issue 3):
  // the 3D clamp and the load distribution differ from the beam's idealisation.
  const double L = 2, b = 0.1, E = 2.1e11, nu = 0.3, G = E / (2 * (1 + nu)), rho = 7850, P = 1000;
  const double A = b * b, I = b * b * b * b / 12, k = 10 * (1 + nu) / (12 + 11 * nu);
  auto mesh = std::shared_ptr<const fem::SolidMesh>(fem::generate_box(Point<3>(L, b, b), {{40, 2, 2}}));
  const fem::Solid body = test_support::steel_solid(mesh, "XMIN");
  const fem::SolidModel model(body);

  // Consistent nodal forces of the traction -P/A e_z on the end face x = L.
  dealii::Vector<double> f(model.n_dofs());
  const dealii::QGauss<2> face_rule(3);
  dealii::FEFaceValues<3> face(model.mapping(), model.dof_handler().get_fe(), face_rule,
                               dealii::update_values | dealii::update_JxW_values | dealii::update_quadrature_points);
  std::vector<dealii::types::global_dof_index> local(model.dof_handler().get_fe().n_dofs_per_cell());
  for (const auto &cell : model.dof_handler().active_cell_iterators())
    for (const auto fn : cell->face_indices())
      if (cell->at_boundary(fn) && std::abs(cell->face(fn)->center()[0] - L) < 1e-9)
        {
          face.reinit(cell, fn);
          cell->get_dof_indices(local);
          for (unsigned int q = 0; q < face_rule.size(); ++q)
            for (unsigned int i = 0; i < local.size(); ++i)
              if (model.dof_handler().get_fe().system_to_component_index(i).first == 2)
                f[local[i]] += -P / A * face.shape_value_component(i, q, 2) * face.JxW(q);
        }
  model.constraints().set_zero(f);
  const auto u = solve_direct(model.stiffness_matrix(), f);
  // Mean vertical displacement of the end face's nodes.
  const auto x = model.support_points();
  double sum = 0;
  unsigned int count = 0;
  std::vector<unsigned int> component(model.n_dofs());
  for (const auto &cell : model.dof_handler().active_cell_iterators())
    {
      cell->get_dof_indices(local);
      for (unsigned int i = 0; i < local.size(); ++i)
        component[local[i]] = model.dof_handler().get_fe().system_to_component_index(i).first;
    }
  for (unsigned int i = 0; i < model.n_dofs(); ++i)
    if (std::abs(x[i][0] - L) < 1e-9 && component[i] == 2)
      {
        sum += u[i];
        ++count;
      }
  const double tip = -sum / count;
  const double timoshenko = P * L * L * L / (3 * E * I) + P * L / (k * G * A);
  std::cout << "  tip deflection " << tip << " m, Timoshenko beam " << timoshenko << " m, rel. diff. "
            << std::abs(tip - timoshenko) / timoshenko << "\n";
  EXPECT_LT(std::abs(tip - timoshenko) / timoshenko, 1e-2);

  reduction::ModalSettings settings;
  settings.n_modes = 1;
  const double f1 = reduction::lowest_modes(model, settings).frequencies_hz()[0];
  const double beam = 1.875104068711961 * 1.875104068711961 * std::sqrt(E * I / (rho * A * std::pow(L, 4))) / (2 * M_PI);
  std::cout << "  first frequency " << f1 << " Hz, Euler-Bernoulli " << beam << " Hz, rel. diff. "
            << std::abs(f1 - beam) / beam << "\n";
  EXPECT_LT(std::abs(f1 - beam) / beam, 1e-2);
}

TEST(Solid, gmsh_meshes_give_the_frequencies_of_the_same_mesh_in_calculix)
{
  // meshes/quarter_ring_hex20.{msh, _v2.msh, inp}: one 20-node mesh written by Gmsh 4.8.4 in
  // MSH 4.1, MSH 2.2 and Abaqus format (curved edges; physical surface FIX). FlexTrack must read
  // the two .msh files identically (1e-12), the .inp to 1e-10 (Gmsh writes its coordinates with
  // fewer digits there), and agree with CalculiX on the .inp (1e-5, issue 3).
  const std::string dir = work_directory("gmsh");
  std::filesystem::copy_file(FLEXTRACK_SOURCE_DIR "/meshes/quarter_ring_hex20.inp", dir + "/quarter_ring_hex20.inp",
                             std::filesystem::copy_options::overwrite_existing);
  const auto ccx = test_support::run_calculix(dir, "quarter_ring_hex20");
  ASSERT_EQ(ccx.size(), 10u) << "CalculiX did not run; see " << dir;
  std::vector<std::vector<double>> f;
  for (const std::string name : {"quarter_ring_hex20.msh", "quarter_ring_hex20_v2.msh", "quarter_ring_hex20.inp"})
    {
      const fem::Solid body = test_support::steel_solid(fem::read_mesh_file(FLEXTRACK_SOURCE_DIR "/meshes/" + name, "test"));
      const fem::SolidModel model(body);
      reduction::ModalSettings settings;
      f.push_back(reduction::lowest_modes(model, settings).frequencies_hz());
    }
  for (unsigned int k = 0; k < 10; ++k)
    {
      std::cout << "  mode " << k + 1 << ": msh 4.1 " << std::setprecision(10) << f[0][k] << ", msh 2.2 " << f[1][k]
                << ", inp " << f[2][k] << ", CalculiX " << ccx[k] << " Hz\n";
      EXPECT_NEAR(f[1][k], f[0][k], 1e-12 * f[0][k]);
      EXPECT_NEAR(f[2][k], f[0][k], 1e-10 * f[0][k]);
      EXPECT_LT(std::abs(f[0][k] - ccx[k]) / ccx[k], 1e-5);
    }
}

TEST(Solid, generated_cylinder_cantilever_matches_beam_theory)
{
  // Steel cylinder R = 0.025 m, L = 2 m (L/d = 40), 40 x 5 hex20 cells with curved hull edges,
  // clamped at x = 0. First two bending frequencies (each twice, by symmetry) against
  // Euler-Bernoulli, (b_n L)^2 sqrt(EI / (rho A L^4)) / (2 pi) (Blevins, Table 8-1); shear,
  // rotary inertia and the 3D clamp shift them by a few 0.1 %: tolerance 1 % (issue 3).
  const double R = 0.025, L = 2, E = 2.1e11, rho = 7850, I = M_PI * std::pow(R, 4) / 4, A = M_PI * R * R;
  const fem::Solid body = test_support::steel_solid(fem::generate_cylinder(R, L, 40), "XMIN");
  const fem::SolidModel model(body);
  reduction::ModalSettings settings;
  settings.n_modes = 4;
  const auto f = reduction::lowest_modes(model, settings).frequencies_hz();
  const double bL[2] = {1.875104068711961, 4.694091132974175};
  for (unsigned int k = 0; k < 4; ++k)
    {
      const double beam = bL[k / 2] * bL[k / 2] * std::sqrt(E * I / (rho * A * std::pow(L, 4))) / (2 * M_PI);
      std::cout << "  mode " << k + 1 << ": " << f[k] << " Hz, Euler-Bernoulli " << beam << " Hz, rel. diff. "
                << std::abs(f[k] - beam) / beam << "\n";
      EXPECT_LT(std::abs(f[k] - beam) / beam, 1e-2);
    }
}
