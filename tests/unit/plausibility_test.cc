// Physical plausibility of reduced bodies (issue 23, item 4; reduction/plausibility.h): real
// reduced bodies pass - clamped and free, Craig-Bampton and free interface - with their known
// properties as references, and each damage of the issue is refused naming the property.
#include <fem/body_model.h>
#include <io/body_scene.h>
#include <reduction/component_modes.h>
#include <reduction/plausibility.h>
#include <reduction/reduced_body_builder.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <tuple>

using namespace flextrack;

namespace
{
const std::string steel = "  subsection Material\n   set Young's modulus = 2.1e11\n   set Poisson's ratio = 0.3\n"
                          "   set Density = 7850\n  end\n";

/// A steel block 0.2 x 0.1 x 0.1 m (hex20, 4 x 2 x 2 cells) with a straight round arm (d = 20 mm,
/// 0.6 m along x) tied rigidly to its face x = 0.2, an interface at the arm's tip and one on the
/// block's top face, a point mass at the tip.
std::string bracket(const std::string &supports, const std::string &method)
{
  return "set Model = body\nsubsection Body\n set Arms = boom\n set Ties = boom: rigid, within 0.03\n"
         " set Interfaces = root: point 0.1 0.05 0.1, within 0.03; tip: arm boom at 0.6\n"
         " set Point masses = tip: 0.5\nend\nsubsection Solid\n set Mesh = box\n set Supports = " +
         supports + "\n subsection Box\n  set Size = 0.2, 0.1, 0.1\n  set Cells = 4, 2, 2\n end\n" + steel +
         "end\nsubsection Arm boom\n subsection Curve\n  set Kind = line\n  subsection Line\n"
         "   set Start point = 0.2, 0.05, 0.05\n   set End point = 0.8, 0.05, 0.05\n  end\n end\n"
         " subsection Cross section\n  set Shape = circle\n  set Diameter = 0.02\n end\n" + steel +
         " subsection Supports\n  set Start = free\n  set End = free\n end\n"
         " subsection Mesh\n  set Number of elements = 12\n end\nend\nsubsection Reduction\n set Method = " + method +
         "\n set Number of normal modes = 6\n set Track arms = boom\n set Track stations = 3\n"
         " set Damping ratio = 0.02\nend\n";
}

reduction::ReducedBody reduced(const std::string &scene_text)
{
  const auto scene = io::read_body_scene_from_string(scene_text);
  const fem::BodyModel model(scene.body);
  return reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), scene.reduction.method_name());
}

/// The message of check_physical_plausibility ("" if it passes).
std::string refusal(const reduction::ReducedBody &body)
{
  try
    {
      reduction::check_physical_plausibility(body);
    }
  catch (const std::runtime_error &e)
    {
      return e.what();
    }
  return "";
}

std::vector<double> eigenvalues(const dealii::FullMatrix<double> &A)
{
  dealii::LAPACKFullMatrix<double> L(A.m());
  L = A;
  L.compute_eigenvalues();
  std::vector<double> e;
  for (unsigned int i = 0; i < A.m(); ++i) e.push_back(L.eigenvalue(i).real());
  std::sort(e.begin(), e.end());
  return e;
}
} // namespace

TEST(Plausibility, reduced_bodies_clamped_and_free_by_both_methods_pass)
{
  // References: the basis is M-orthonormal and rotated onto the reduced eigenvectors
  // (reduction/component_modes.h), so M = 1 and the eigenvalues of K are (2 pi f_k)^2 to
  // round-off; the mass is that of the block, the arm and the point mass: 7850 (0.002 + 0.6 pi
  // 0.01^2) + 0.5 = 17.68 kg. The checks must pass with margins of orders of magnitude
  // (printed): M's condition number is 1, K's smallest eigenvalue is w_1^2 > 0.
  for (const auto &[supports, method] : {std::make_pair("XMIN: x, y, z", "craig bampton"),
                                         std::make_pair("", "craig bampton"), std::make_pair("", "free interface")})
    {
      const auto body = reduced(bracket(supports, method));
      const unsigned int n = body.n_modes();
      const auto start = std::chrono::steady_clock::now();
      EXPECT_EQ(refusal(body), "") << supports << " " << method;
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const auto m = eigenvalues(body.mass), k = eigenvalues(body.stiffness);
      const auto J = dealii::eigenvalues(dealii::symmetrize(body.invariants.inertia_origin));
      std::cout << (*supports ? "clamped, " : "free, ") << method << ", " << n << " modes: M eigenvalues " << m.front()
                << " ... " << m.back() << ", K eigenvalues " << k.front() << " ... " << k.back() << " N/m, mass "
                << body.invariants.mass << " kg, J_O moments " << J[2] << ", " << J[1] << ", " << J[0]
                << " kg m^2; checked in " << seconds << " s\n";
      EXPECT_NEAR(m.front(), 1, 1e-9);
      EXPECT_NEAR(m.back(), 1, 1e-9);
      EXPECT_GT(k.front(), 0);
      const double w1 = 2 * M_PI * body.frequencies_hz[0];
      EXPECT_NEAR(k.front(), w1 * w1, 1e-8 * k.back());
      EXPECT_NEAR(body.invariants.mass, 7850 * (0.002 + 0.6 * M_PI * 1e-4) + 0.5, 1e-9 * body.invariants.mass);
      EXPECT_GT(J[1] + J[2], J[0]);
    }
}

TEST(Plausibility, each_damage_of_issue_23_is_refused_naming_the_property)
{
  const auto valid = reduced(bracket("XMIN: x, y, z", "craig bampton"));
  const unsigned int n = valid.n_modes();
  ASSERT_EQ(refusal(valid), "");
  const double largest = eigenvalues(valid.stiffness).back();
  const double w1_squared = std::pow(2 * M_PI * valid.frequencies_hz[0], 2);
  const std::vector<std::tuple<std::string, std::function<void(reduction::ReducedBody &)>, std::string>> cases = {
    {"mass -1 kg", [](auto &b) { b.invariants.mass = -1; },
     "the mass (/inertia/mass) is not positive (-1.00e+00 kg)"},
    {"all-zero mass matrix", [](auto &b) { b.mass = 0; },
     "the reduced mass matrix (/reduced/mass) is not positive definite (smallest eigenvalue 0.00e+00 kg, largest "
     "0.00e+00 kg)"},
    {"M[0][0] = -0.32", [](auto &b) { b.mass(0, 0) = -0.32; },
     "the reduced mass matrix (/reduced/mass) is not positive definite (smallest eigenvalue -3.20e-01 kg, largest "
     "1.00e+00 kg)"},
    {"-K", [](auto &b) { b.stiffness *= -1; },
     "the reduced stiffness matrix (/reduced/stiffness) is not positive semi-definite (smallest eigenvalue -"},
    {"K[0,1] = 1e12", [](auto &b) { b.stiffness(0, 1) = 1e12; },
     "the reduced stiffness matrix (/reduced/stiffness) is not symmetric: [0,1] = 1.00e+12 N/m"},
    // The tolerance of semi-definiteness: 1e-8 of the largest eigenvalue (rigid-body round-off)
    // is allowed, 1e-6 is not.
    {"K shifted to -1e-6 of its largest eigenvalue",
     [&](auto &b) { b.stiffness.diagadd(-(w1_squared + 1e-6 * largest)); },
     "the reduced stiffness matrix (/reduced/stiffness) is not positive semi-definite"},
    {"damping -100 I", [&](auto &b) { b.damping = dealii::IdentityMatrix(n); b.damping *= -100; },
     "the symmetric part of the reduced damping matrix (/reduced/damping) is not positive semi-definite (smallest "
     "eigenvalue -1.00e+02 N s/m"},
    {"negative frequency", [](auto &b) { b.frequencies_hz[2] = -100; }, // the largest is 18 kHz
     "frequency 2 (/reduced/frequencies_hz) is negative (-1.00e+02 Hz; allowed down to -1.00e-04 of the largest"},
    {"J_O = diag(1, 1, 3)", [](auto &b) { b.invariants.inertia_origin = dealii::Tensor<2, 3>({{1, 0, 0}, {0, 1, 0}, {0, 0, 3}}); },
     "the inertia tensor about the origin (/inertia/inertia_origin) has principal moments 1.00e+00, 1.00e+00, 3.00e+00 "
     "kg m^2 that violate the triangle inequality J1 + J2 >= J3"},
    {"J_O negative", [](auto &b) { b.invariants.inertia_origin *= -1; },
     "the inertia tensor about the origin (/inertia/inertia_origin) has a principal moment that is not positive"},
    {"J_O[0][1] changed", [](auto &b) { b.invariants.inertia_origin[0][1] += 1; },
     "the inertia tensor about the origin (/inertia/inertia_origin) is not symmetric: [0,1]"},
    {"first moment 100 times", [](auto &b) { b.invariants.first_moment *= 100; },
     "the inertia tensor about the centre of mass (from /inertia/mass, first_moment and inertia_origin) is not positive "
     "semi-definite"}};
  for (const auto &[name, damage, expected] : cases)
    {
      auto body = valid;
      damage(body);
      const std::string message = refusal(body);
      std::cout << name << ": " << message << "\n";
      EXPECT_NE(message.find(expected), std::string::npos) << name << ": " << message;
    }
  // Within the tolerance: K shifted to -1e-10 of its largest eigenvalue, as round-off of a
  // rigid-body mode would leave it, and a relative asymmetry of 1e-10, pass.
  // So does the frequency of that eigenvalue (signed square root, as reduction/modal_solver.h):
  // -1e-5 of the largest frequency; -1e-3 does not.
  auto body = valid;
  body.stiffness.diagadd(-(w1_squared + 1e-10 * largest));
  body.stiffness(0, 1) += 1e-10 * largest;
  body.frequencies_hz[0] = -1e-5 * body.frequencies_hz.back();
  EXPECT_EQ(refusal(body), "");
  body.frequencies_hz[0] = -1e-3 * body.frequencies_hz.back();
  EXPECT_NE(refusal(body).find("frequency 0 (/reduced/frequencies_hz) is negative"), std::string::npos) << refusal(body);
}

TEST(Plausibility, checks_of_a_300_mode_body_cost_a_fraction_of_a_second)
{
  // The cost on every read: three symmetric eigenvalue problems of size n (LAPACK dsyev, about
  // 4 n^3 / 3 flops each without vectors). n = 300 is beyond the largest body of the test and
  // sample scenes (47 modes); dense random SPD matrices B^T B / n + 1 stand in for M, K, C. A
  // valid body of that size must pass; the time is printed (0.03 s measured in Release).
  auto body = reduced(bracket("XMIN: x, y, z", "craig bampton"));
  const unsigned int n = 300;
  std::mt19937 random(23);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (auto *A : {&body.mass, &body.stiffness, &body.damping})
    {
      dealii::FullMatrix<double> B(n, n);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j) B(i, j) = uniform(random);
      A->reinit(n, n);
      B.Tmmult(*A, B);
      *A *= 1.0 / n;
      A->diagadd(1);
    }
  body.frequencies_hz.assign(n, 1);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(refusal(body), "");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "checks of a body of " << n << " modes: " << seconds << " s\n";
}
