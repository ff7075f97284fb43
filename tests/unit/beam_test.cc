// Natural frequencies of the curved beam model against published closed forms.
#include <fem/curved_beam_model.h>
#include <io/arm_scene.h>
#include <reduction/modal_solver.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/component_mask.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>

using namespace flextrack;

namespace
{
struct Result
{
  std::vector<double> f;                  // Hz, ascending
  std::vector<std::array<double, 6>> share; // kinetic-energy share of u_x..u_z, theta_x..theta_z
};

/// Modal analysis of the arm described by @p prm_text, refined @p refinement times.
Result modes_of(const std::string &prm_text, const unsigned int refinement = 0)
{
  dealii::ParameterHandler prm;
  io::declare_arm_scene(prm);
  const io::ArmScene scene = io::read_arm_scene_from_string(prm_text, prm);
  const fem::CurvedBeamModel model(scene.arm, refinement);
  const reduction::Modes modes = reduction::lowest_modes(model, scene.modal);
  Result r;
  r.f = modes.frequencies_hz();
  // Which component carries a mode's kinetic energy: phi_i (M phi)_i summed per component.
  std::vector<unsigned int> component(model.n_dofs());
  for (unsigned int c = 0; c < 6; ++c)
    {
      std::vector<bool> mask(6, false);
      mask[c] = true;
      const auto set = dealii::DoFTools::extract_dofs(model.dof_handler(), dealii::ComponentMask(mask));
      for (const auto i : set) component[i] = c;
    }
  for (const auto &phi : modes.shapes)
    {
      dealii::Vector<double> Mphi(phi.size());
      model.mass_matrix().vmult(Mphi, phi);
      std::array<double, 6> e{};
      for (unsigned int i = 0; i < phi.size(); ++i) e[component[i]] += phi[i] * Mphi[i];
      r.share.push_back(e);
    }
  return r;
}

std::string straight(double L, const std::string &section, unsigned int elements, unsigned int degree,
                     unsigned int n_modes)
{
  return "subsection Arm\n subsection Curve\n  set Kind = line\n  subsection Line\n   set End point = " +
         std::to_string(L) + ", 0, 0\n  end\n end\n subsection Cross section\n" + section +
         " end\n subsection Material\n  set Young's modulus = 2.1e11\n  set Poisson's ratio = 0.3\n"
         "  set Density = 7850\n end\n subsection Supports\n  set Start = clamped\n end\n subsection Mesh\n  set Number of elements = " +
         std::to_string(elements) + "\n  set Element degree = " + std::to_string(degree) +
         "\n end\nend\nsubsection Modal analysis\n set Number of modes = " + std::to_string(n_modes) + "\nend\n";
}

double relative(double a, double b) { return std::abs(a - b) / std::abs(b); }

/// Log line for the test output: computed value, reference, relative error.
void report(const std::string &what, double computed, double reference)
{
  std::cout << "  " << std::left << std::setw(28) << what << std::right << std::setprecision(10) << std::setw(18)
            << computed << std::setw(18) << reference << std::setw(12) << std::setprecision(2) << std::scientific
            << relative(computed, reference) << std::defaultfloat << "\n";
}
} // namespace

TEST(CurvedBeam, slender_cantilever_bending_frequencies_match_euler_bernoulli)
{
  // L = 3 m, solid circle d = 0.01 m (L/d = 300), steel. Euler-Bernoulli cantilever:
  // w_n = (b_n L)^2 sqrt(EI / (rho A L^4)), b_n L from Blevins, Formulas for Natural Frequency
  // and Mode Shape, Table 8-1 (REFERENCES.md sec. 1). Shear and rotary inertia change the 4th
  // frequency by ~0.02 %; tolerance 0.1 % (issue 2).
  const double L = 3, d = 0.01, E = 2.1e11, rho = 7850;
  const double A = M_PI * d * d / 4, I = M_PI * std::pow(d, 4) / 64;
  const Result r = modes_of(straight(L, "  set Shape = circle\n  set Diameter = 0.01\n", 24, 2, 8));
  const double bL[] = {1.875104068711961, 4.694091132974175, 7.854757438237613, 10.99554073487547};
  for (int n = 0; n < 4; ++n)
    {
      const double exact = bL[n] * bL[n] * std::sqrt(E * I / (rho * A * std::pow(L, 4))) / (2 * M_PI);
      // A circle bends alike in both planes: each frequency appears twice.
      report("bending " + std::to_string(n + 1), r.f[2 * n], exact);
      EXPECT_LT(relative(r.f[2 * n], exact), 1e-3) << "bending mode " << n + 1;
      EXPECT_LT(relative(r.f[2 * n + 1], exact), 1e-3) << "bending mode " << n + 1 << " (other plane)";
    }
}

TEST(CurvedBeam, slender_cantilever_first_torsion_and_axial_frequencies_match_closed_forms)
{
  // Fixed-free rod: w_1 = pi / (2L) sqrt(E / rho) (axial), pi / (2L) sqrt(G J / (rho Ip)) with
  // J = Ip for a circle (torsion) (REFERENCES.md sec. 1). Tolerance 0.1 %. The torsion and axial
  // modes are found among the bending modes by their kinetic energy (theta_x resp. u_x).
  const double L = 3, E = 2.1e11, G = E / 2.6, rho = 7850;
  const Result r = modes_of(straight(L, "  set Shape = circle\n  set Diameter = 0.01\n", 48, 3, 40));
  double torsion = NAN, axial = NAN;
  for (std::size_t k = 0; k < r.f.size(); ++k)
    {
      if (std::isnan(torsion) && r.share[k][3] > 0.9) torsion = r.f[k];
      if (std::isnan(axial) && r.share[k][0] > 0.9) axial = r.f[k];
    }
  ASSERT_FALSE(std::isnan(torsion)) << "no torsion mode among the lowest 40";
  ASSERT_FALSE(std::isnan(axial)) << "no axial mode among the lowest 40";
  report("torsion 1", torsion, M_PI / (2 * L) * std::sqrt(G / rho) / (2 * M_PI));
  report("axial 1", axial, M_PI / (2 * L) * std::sqrt(E / rho) / (2 * M_PI));
  EXPECT_LT(relative(torsion, M_PI / (2 * L) * std::sqrt(G / rho) / (2 * M_PI)), 1e-3);
  EXPECT_LT(relative(axial, M_PI / (2 * L) * std::sqrt(E / rho) / (2 * M_PI)), 1e-3);
}

TEST(CurvedBeam, thick_cantilever_matches_timoshenko_beam_theory)
{
  // L = 1 m, square a = 0.1 m (L/a = 10), steel: Timoshenko beam with Cowper's shear factor,
  // rotary inertia; torsion with J = 0.140577015 a^4, Ip = a^4/6; axial rod
  // (REFERENCES.md sec. 1, derived from the Timoshenko beam equations). Tolerance 0.1 %.
  // Modes are sorted into bending, torsion (theta_x) and axial (u_x) by their kinetic energy;
  // above 2375.8 Hz the 5th bending pair (not in the reference) precedes the 2nd axial mode.
  const std::vector<double> bending = {82.9038, 497.1761, 1308.6493, 2375.8083};
  const std::vector<double> torsion = {736.4800, 2209.4399}, axial = {1293.0485, 3879.1456};
  const Result r = modes_of(straight(1.0, "  set Shape = rectangle\n  set Width = 0.1\n  set Height = 0.1\n",
                                     32, 3, 16));
  std::vector<double> found_bending, found_torsion, found_axial;
  for (std::size_t k = 0; k < r.f.size(); ++k)
    (r.share[k][3] > 0.9 ? found_torsion : r.share[k][0] > 0.9 ? found_axial : found_bending).push_back(r.f[k]);
  ASSERT_GE(found_bending.size(), 8u);
  ASSERT_GE(found_torsion.size(), 2u);
  ASSERT_GE(found_axial.size(), 2u);
  for (std::size_t n = 0; n < bending.size(); ++n)
    for (std::size_t plane = 0; plane < 2; ++plane) // a square bends alike in both planes
      {
        report("bending " + std::to_string(n + 1) + (plane ? "b" : "a"), found_bending[2 * n + plane], bending[n]);
        EXPECT_LT(relative(found_bending[2 * n + plane], bending[n]), 1e-3)
          << "bending " << n + 1 << ": " << found_bending[2 * n + plane] << " Hz";
      }
  for (std::size_t n = 0; n < 2; ++n)
    {
      report("torsion " + std::to_string(n + 1), found_torsion[n], torsion[n]);
      report("axial " + std::to_string(n + 1), found_axial[n], axial[n]);
      EXPECT_LT(relative(found_torsion[n], torsion[n]), 1e-3) << "torsion " << n + 1 << ": " << found_torsion[n];
      EXPECT_LT(relative(found_axial[n], axial[n]), 1e-3) << "axial " << n + 1 << ": " << found_axial[n];
    }
}

TEST(CurvedBeam, free_ring_matches_hoppe_and_out_of_plane_closed_forms)
{
  // Free thin circular ring, R = 1 m, solid circle d = 0.01 m (R/d = 100), steel.
  // In-plane inextensional bending (Hoppe 1871; Blevins, Table 9-1):
  //   w_n = sqrt(EI / (rho A R^4)) n (n^2 - 1) / sqrt(n^2 + 1)
  // Out-of-plane bending-torsion (Blevins, Table 9-1; Rao, Vibration of Continuous Systems):
  //   w_n = sqrt(EI / (rho A R^4)) n (n^2 - 1) / sqrt(n^2 + EI / GJ),  EI / GJ = 1 + nu (circle).
  // Both neglect shear, extension and rotary inertia: O((d/R)^2 n^2) ~ 1e-4 here. Tolerance 0.1 %.
  // The first 6 modes are rigid-body motions: zero frequency (to 1e-4 of the first elastic one).
  const double R = 1, d = 0.01, E = 2.1e11, nu = 0.3, rho = 7850;
  const double A = M_PI * d * d / 4, I = M_PI * std::pow(d, 4) / 64;
  const double scale = std::sqrt(E * I / (rho * A * std::pow(R, 4))) / (2 * M_PI);
  const std::string prm =
    "subsection Arm\n subsection Curve\n  set Kind = arc\n  subsection Arc\n   set Radius = 1\n"
    "   set Angle = 6.283185307179586\n  end\n end\n subsection Cross section\n  set Shape = circle\n"
    "  set Diameter = 0.01\n end\n subsection Supports\n  set Start = free\n  set End = free\n end\n"
    " subsection Mesh\n  set Number of elements = 64\n  set Element degree = 2\n end\nend\n"
    "subsection Modal analysis\n set Number of modes = 14\nend\n";
  const Result r = modes_of(prm);
  (void)R;
  std::vector<double> reference;
  for (const double n : {2.0, 3.0})
    {
      const double in_plane = scale * n * (n * n - 1) / std::sqrt(n * n + 1);
      const double out_of_plane = scale * n * (n * n - 1) / std::sqrt(n * n + 1 + nu);
      reference.insert(reference.end(), {out_of_plane, out_of_plane, in_plane, in_plane});
    }
  std::sort(reference.begin(), reference.end());
  for (int k = 0; k < 6; ++k)
    {
      std::cout << "  rigid-body mode " << k + 1 << ": " << r.f[k] << " Hz\n";
      EXPECT_LT(std::abs(r.f[k]), 1e-4 * reference[0]) << "rigid-body mode " << k + 1;
    }
  for (std::size_t k = 0; k < reference.size(); ++k)
    {
      report("elastic mode " + std::to_string(k + 1), r.f[6 + k], reference[k]);
      EXPECT_LT(relative(r.f[6 + k], reference[k]), 1e-3) << "elastic mode " << k + 1 << ": " << r.f[6 + k];
    }
}

TEST(CurvedBeam, observed_convergence_order_is_twice_the_element_degree)
{
  // Galerkin eigenvalue error is O(h^{2p}) for elements of degree p (Strang & Fix, An Analysis
  // of the Finite Element Method, ch. 6); reduced integration with p Gauss points keeps it
  // (the rule is exact for degree 2p - 1). Quarter-circle cantilever, R = 1 m, tube, first
  // bending mode; observed order log2(|f_{k-1} - f_{k-2}| / |f_k - f_{k-1}|) on three nested
  // meshes. Tolerance 0.35 on the order (pre-asymptotic effects).
  for (unsigned int p = 1; p <= 3; ++p)
    {
      const std::string prm =
        "subsection Arm\n subsection Curve\n  set Kind = arc\n end\n subsection Cross section\n"
        "  set Shape = tube\n end\n subsection Supports\n  set Start = clamped\n end\n subsection Mesh\n  set Number of elements = 2\n"
        "  set Element degree = " + std::to_string(p) +
        "\n end\nend\nsubsection Modal analysis\n set Number of modes = 3\nend\n";
      // Meshes in the asymptotic range: 8-16-32 (p = 1), 2-4-8 (p = 2), 4-8-16 (p = 3).
      const unsigned int first = p == 1 ? 2 : p == 3 ? 1 : 0;
      std::vector<double> f;
      for (unsigned int k = first; k < first + 3; ++k) f.push_back(modes_of(prm, k).f[2]);
      const double order = std::log2(std::abs((f[1] - f[0]) / (f[2] - f[1])));
      std::cout << "degree " << p << ": elements " << (2u << first) << ", " << (4u << first) << ", " << (8u << first)
                << ": f = " << std::setprecision(12) << f[0] << ", " << f[1] << ", " << f[2]
                << " Hz; observed order " << std::setprecision(3) << order << " (theory " << 2 * p << ")\n";
      EXPECT_NEAR(order, 2.0 * p, 0.35) << "degree " << p << ": frequencies " << f[0] << " " << f[1] << " " << f[2];
    }
}

TEST(Scene, json_and_prm_files_describe_the_same_scene)
{
  // deal.II's ParameterHandler reads .json as well as .prm: the same arm in both formats must
  // give the same frequencies (bit for bit: same parameters, same computation).
  std::vector<std::vector<double>> f;
  for (const std::string file : {"quarter_ring.json", "quarter_ring.prm"})
    {
      dealii::ParameterHandler prm;
      io::declare_arm_scene(prm);
      const io::ArmScene scene = io::read_arm_scene(FLEXTRACK_TEST_DIR "/input/" + file, prm);
      const fem::CurvedBeamModel model(scene.arm);
      f.push_back(reduction::lowest_modes(model, scene.modal).frequencies_hz());
    }
  ASSERT_EQ(f[0].size(), 3u);
  for (unsigned int k = 0; k < 3; ++k) EXPECT_EQ(f[0][k], f[1][k]) << "mode " << k + 1;
}
