// Modal participation factors and effective masses (issue 12 item 4) in translation and
// rotation, and the classification of modes, on a uniform cantilever against closed forms
// (Euler-Bernoulli, rods; REFERENCES.md section 8) and on a free solid box against its rigid-body
// inertia.
#include <fem/curved_beam_model.h>
#include <fem/solid_model.h>
#include <io/arm_scene.h>
#include <reduction/modal_participation.h>
#include <reduction/modal_solver.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

using namespace flextrack;

namespace
{
/// A steel cantilever along x, clamped at x = 0 (the default support), rectangle Width (section
/// y = global z, the default reference vector) x Height (section z = global -y).
std::string cantilever(const double L, const double width, const double height, const unsigned int elements,
                       const unsigned int n_modes)
{
  return "subsection Arm\n subsection Curve\n  set Kind = line\n  subsection Line\n   set End point = " +
         std::to_string(L) + ", 0, 0\n  end\n end\n subsection Cross section\n  set Shape = rectangle\n  set Width = " +
         std::to_string(width) + "\n  set Height = " + std::to_string(height) +
         "\n end\n subsection Supports\n  set Start = clamped\n end\n subsection Mesh\n  set Number of elements = " + std::to_string(elements) +
         "\n  set Element degree = 3\n end\nend\nsubsection Modal analysis\n set Number of modes = " +
         std::to_string(n_modes) + "\nend\n";
}

/// Every mode of @p model (dense LAPACK on the free dofs), mass-normalised, as full-length vectors.
std::vector<dealii::Vector<double>> all_modes(const fem::CurvedBeamModel &model)
{
  std::vector<unsigned int> free;
  for (unsigned int i = 0; i < model.n_dofs(); ++i)
    if (!model.constraints().is_constrained(i)) free.push_back(i);
  const unsigned int n = free.size();
  dealii::LAPACKFullMatrix<double> K(n, n), M(n, n);
  for (unsigned int a = 0; a < n; ++a)
    for (unsigned int b = 0; b < n; ++b)
      {
        K(a, b) = model.stiffness_matrix().el(free[a], free[b]);
        M(a, b) = model.mass_matrix().el(free[a], free[b]);
      }
  std::vector<dealii::Vector<double>> eigenvectors(n, dealii::Vector<double>(n));
  K.compute_generalized_eigenvalues_symmetric(M, eigenvectors); // Z^T M Z = I
  std::vector<dealii::Vector<double>> shapes(n, dealii::Vector<double>(model.n_dofs()));
  for (unsigned int k = 0; k < n; ++k)
    for (unsigned int a = 0; a < n; ++a) shapes[k][free[a]] = eigenvectors[k][a];
  return shapes;
}
} // namespace

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
    " subsection Supports\n  set Start = clamped\n end\n subsection Mesh\n  set Number of elements = 64\n  set Element degree = 3\n end\nend\n"
    "subsection Modal analysis\n set Number of modes = 24\nend\n",
    prm);
  const fem::CurvedBeamModel model(scene.arm);
  const auto modes = reduction::lowest_modes(model, scene.modal);
  const auto p = reduction::modal_participation(modes.shapes, model.mass_matrix(), reduction::dof_layout(model));
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

TEST(ModalParticipation, cantilever_rotational_effective_masses_of_all_modes_sum_to_its_moment_of_inertia)
{
  // Steel cantilever along x, L = 1 m, rectangle 0.02 (global z) x 0.03 (global y), 8 cubic
  // elements (144 free dofs), every mode by dense LAPACK. Rotation about the z axis through the
  // clamp (the default reference point, the origin): r = x e_y in the displacements, 1 in the
  // rotation about z. Closed form of r^T M r: rho A L^3 / 3 + rho I L, I = w h^3 / 12 the
  // section's rotary inertia about z, less the clamp node's share of the rotary inertia (its
  // rotation is fixed, its row and column of M are zero): rho I h (2 int N0 - int N0^2) =
  // rho I h (2/12 - 1/14) for deal.II's cubic FE_Q, whose nodes are the Gauss-Lobatto points
  // (int N0 = 1/12, the Lobatto weight; int N0^2 = 1/14, its consistent mass entry). The
  // consistent mass integrates this exactly (4 Gauss points, degree 6): tolerance 1e-12 relative.
  dealii::ParameterHandler prm;
  io::declare_arm_scene(prm);
  const double L = 1, w = 0.02, h = 0.03, rho = 7850, he = L / 8;
  const auto scene = io::read_arm_scene_from_string(cantilever(L, w, h, 8, 4), prm);
  const fem::CurvedBeamModel model(scene.arm);
  const auto shapes = all_modes(model);
  ASSERT_EQ(shapes.size(), model.n_free_dofs());
  const auto p = reduction::modal_participation(shapes, model.mass_matrix(), reduction::dof_layout(model));
  const double A = w * h, I = w * h * h * h / 12;
  const double inertia = rho * A * L * L * L / 3 + rho * I * (L - he * (2.0 / 12 - 1.0 / 14));
  double sum_rz = 0, sum_y = 0;
  for (const auto &m : p.effective_mass)
    {
      sum_rz += m[5];
      sum_y += m[1];
    }
  std::cout << "  rz: r^T M r = " << std::setprecision(15) << p.total_mass[5] << " kg m^2, closed form " << inertia
            << ", sum over all " << shapes.size() << " modes " << sum_rz << "\n  y: r^T M r = " << p.total_mass[1]
            << " kg, rho A L = " << rho * A * L << ", sum over all modes " << sum_y << "\n";
  EXPECT_NEAR(p.total_mass[5] / inertia, 1, 1e-12);
  // Completeness of the modes (Phi Phi^T M = I on the free dofs): the sum over ALL modes is
  // r^T M r up to LAPACK's round-off, 1e-10 relative.
  EXPECT_NEAR(sum_rz / p.total_mass[5], 1, 1e-10);
  EXPECT_NEAR(sum_y / p.total_mass[1], 1, 1e-10);
  // Translation along y: the whole mass rho A L less the clamp node's share rho A h (2/12 - 1/14)
  // (its displacement is fixed), exactly integrated: 1e-12 relative.
  EXPECT_NEAR(p.total_mass[1] / (rho * A * (L - he * (2.0 / 12 - 1.0 / 14))), 1, 1e-12);
}

TEST(ModalParticipation, cantilever_mode_classes_follow_the_closed_form_frequency_order)
{
  // Steel cantilever along x, L = 1 m, rectangle Width 0.02 m (section y) x Height 0.03 m
  // (section z), 32 cubic elements, 12 modes. Closed forms (REFERENCES.md section 8):
  // bending in-plane (deflection along section y, stiffness E Iz, Iz = h w^3/12) and
  // out-of-plane (E Iy, Iy = w h^3/12): f = (beta_n L)^2 / (2 pi) sqrt(E I / (rho A L^4)),
  // beta_n L = 1.8751, 4.6941, 7.8548, 10.9955, 14.1372, 17.2788 (Euler-Bernoulli);
  // torsion f = (2n-1) (pi/2) sqrt(G J / (rho Ip)) / L / (2 pi) with the Saint-Venant J of the
  // rectangle (Timoshenko & Goodier series) and Ip = Iy + Iz; axial f = (2n-1) (pi/2)
  // sqrt(E / rho) / L / (2 pi). Sorted, the first 11 are in-1 16.7, out-1 25.1, in-2 104.7,
  // out-2 157.1, in-3 293.2, out-3 439.8, in-4 574.6, torsion-1 681.8, out-4 861.9, in-5 949.9,
  // axial-1 1293.0 Hz, then in-6 1418.9 and out-5 1424.8 Hz (too close to order: not checked):
  // neighbours differ by 9.7 % or more, the shear and rotary inertia corrections of these
  // bending modes (Timoshenko beam) are at most about 2 % (measured: 1.5 % for in-5), so the
  // order, and the labels, are those of the closed forms.
  dealii::ParameterHandler prm;
  io::declare_arm_scene(prm);
  const double L = 1, w = 0.02, h = 0.03, E = 210e9, nu = 0.3, rho = 7850, G = E / (2 * (1 + nu));
  const auto scene = io::read_arm_scene_from_string(cantilever(L, w, h, 32, 12), prm);
  const fem::CurvedBeamModel model(scene.arm);
  const auto modes = reduction::lowest_modes(model, scene.modal);
  const auto layout = reduction::dof_layout(model);
  const auto p = reduction::modal_participation(modes.shapes, model.mass_matrix(), layout);
  const auto classes = reduction::classify_modes(modes.shapes, model.mass_matrix(), layout, p);
  const std::vector<double> f = modes.frequencies_hz();

  const double A = w * h, Iy = w * h * h * h / 12, Iz = h * w * w * w / 12;
  const double a = std::max(w, h), b = std::min(w, h);
  double series = 0;
  for (int n = 1; n < 40; n += 2) series += std::tanh(n * M_PI * a / (2 * b)) / std::pow(n, 5);
  const double J = a * b * b * b * (1.0 / 3 - 64 * b / (std::pow(M_PI, 5) * a) * series);
  std::vector<std::pair<double, std::string>> closed;
  for (const double beta : {1.875104, 4.694091, 7.854757, 10.995541, 14.137168, 17.278760})
    {
      closed.push_back({beta * beta / (2 * M_PI) * std::sqrt(E * Iz / (rho * A)) / (L * L), "bending in-plane"});
      closed.push_back({beta * beta / (2 * M_PI) * std::sqrt(E * Iy / (rho * A)) / (L * L), "bending out-of-plane"});
    }
  for (int n = 1; n <= 3; ++n)
    {
      closed.push_back({(2 * n - 1) * M_PI / 2 * std::sqrt(G * J / (rho * (Iy + Iz))) / L / (2 * M_PI), "torsion"});
      closed.push_back({(2 * n - 1) * M_PI / 2 * std::sqrt(E / rho) / L / (2 * M_PI), "axial"});
    }
  std::sort(closed.begin(), closed.end());
  ASSERT_EQ(classes.size(), 12u);
  for (unsigned int k = 0; k < 11; ++k)
    {
      std::cout << "  mode " << std::setw(2) << k + 1 << std::setw(10) << std::setprecision(5) << f[k] << " Hz  "
                << std::setw(21) << classes[k].kind << " (share " << std::setprecision(12) << classes[k].share
                << ")   closed form " << std::setprecision(5) << closed[k].first << " Hz " << closed[k].second << "\n";
      EXPECT_EQ(classes[k].kind, closed[k].second) << "mode " << k + 1;
      // Straight arm: the section frame is constant, the four families decouple exactly, and
      // each mode's energy lies in one of them up to round-off: 1e-9.
      EXPECT_NEAR(classes[k].share, 1, 1e-9) << "mode " << k + 1;
    }
  // The first mode of each kind against its closed form. Axial and torsion: the beam's equations
  // are exactly those of the rods (same J, no warping), the rest is the discretisation error of
  // 32 cubic elements (below 1e-8): 1e-6 relative. First bending in each plane: shear and rotary
  // inertia lower them by about (beta r)^2 (1 + E / (k G)) / 2 = 2.4e-4 (in-plane, r = w/sqrt 12)
  // and 5.4e-4 (out-of-plane) (measured 3.1e-4 and 7.1e-4): 1e-3 relative.
  auto first = [&](const std::string &kind) {
    for (unsigned int k = 0; k < 11; ++k)
      if (classes[k].kind == kind) return k;
    return 11u;
  };
  auto closed_first = [&](const std::string &kind) {
    for (const auto &c : closed)
      if (c.second == kind) return c.first;
    return 0.0;
  };
  for (const auto &[kind, tolerance] : std::vector<std::pair<std::string, double>>{
         {"axial", 1e-6}, {"torsion", 1e-6}, {"bending in-plane", 1e-3}, {"bending out-of-plane", 1e-3}})
    {
      const unsigned int k = first(kind);
      ASSERT_LT(k, 11u) << kind;
      std::cout << "  first " << kind << ": mode " << k + 1 << ", " << std::setprecision(10) << f[k]
                << " Hz, closed form " << closed_first(kind) << " Hz, relative difference "
                << f[k] / closed_first(kind) - 1 << "\n";
      EXPECT_NEAR(f[k] / closed_first(kind), 1, tolerance) << kind;
    }
}

TEST(ModalParticipation, free_solid_box_rigid_modes_carry_its_mass_and_moments_of_inertia)
{
  // A free steel box 1 x 0.1 x 0.2 m (generated hex20 mesh from the origin), 8 modes: six rigid
  // ones and two elastic. About axes through the centroid (reference point 0.5, 0.05, 0.1) its
  // rigid-body inertia is m (b^2 + c^2) / 12 etc. (closed form); the 20-node geometry places the
  // serendipity nodes exactly on the affine cells and the 3^3 Gauss rule integrates the
  // quadratic r . r exactly: totals 1e-12 relative. The six rigid modes span every rigid motion,
  // so their effective masses sum to the totals in each direction, up to ARPACK's accuracy of
  // the near-zero modes (tolerance 1e-12 on the eigenvalues; measured within 1e-12): 1e-9; the
  // elastic modes are M-orthogonal to rigid motions and carry none (measured 1e-26): 1e-9.
  dealii::ParameterHandler prm;
  io::declare_arm_scene(prm);
  const auto scene = io::read_arm_scene_from_string(
    "set Model = solid\nsubsection Solid\n set Mesh = box\n subsection Box\n  set Size = 1, 0.1, 0.2\n"
    "  set Cells = 5, 1, 1\n end\n set Supports =\nend\n"
    "subsection Modal analysis\n set Number of modes = 8\n set Participation reference point = 0.5, 0.05, 0.1\nend\n",
    prm);
  const fem::SolidModel model(scene.solid);
  const auto modes = reduction::lowest_modes(model, scene.modal);
  const dealii::Point<3> x_ref(scene.modal.participation_reference[0], scene.modal.participation_reference[1],
                               scene.modal.participation_reference[2]);
  const auto p = reduction::modal_participation(modes.shapes, model.mass_matrix(), reduction::dof_layout(model), x_ref);
  const double a = 1, b = 0.1, c = 0.2, m = 7850 * a * b * c;
  const std::array<double, 6> total = {{m, m, m, m * (b * b + c * c) / 12, m * (a * a + c * c) / 12,
                                        m * (a * a + b * b) / 12}};
  for (unsigned int d = 0; d < 6; ++d)
    {
      double rigid = 0, elastic = 0;
      for (unsigned int k = 0; k < 8; ++k) (k < 6 ? rigid : elastic) += p.fraction(k, d);
      std::cout << "  " << reduction::rigid_direction_names[d] << ": r^T M r " << std::setprecision(12)
                << p.total_mass[d] << ", closed form " << total[d] << "; six rigid modes carry 1 + " << rigid - 1
                << ", two elastic " << elastic << "\n";
      EXPECT_NEAR(p.total_mass[d] / total[d], 1, 1e-12) << reduction::rigid_direction_names[d];
      EXPECT_NEAR(rigid, 1, 1e-9) << reduction::rigid_direction_names[d];
      EXPECT_NEAR(elastic, 0, 1e-9) << reduction::rigid_direction_names[d];
    }
}
