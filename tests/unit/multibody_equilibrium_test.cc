// Static equilibrium as the initial state (issue 9 item 8; multibody/static_equilibrium.h):
//  - a reduced cantilever under its own weight sags by q L^4 / (8 E I) at the tip (Euler-Bernoulli
//    closed form, e.g. Timoshenko & Gere, Mechanics of Materials, table of beam deflections), and a
//    run started there stays at rest, while the same run started straight oscillates about it;
//  - a pendulum started off its rest position swings back to it; started near the top it finds
//    the inverted equilibrium and the report calls it unstable;
//  - a mechanism under the loads (a slider on a level guide) is refused, naming the free motion.
// Units: SI.
#include "multibody_test_helpers.h"

#include <base/input_error.h>
#include <fem/body_model.h>
#include <io/body_scene.h>
#include <multibody/force.h>
#include <multibody/static_stiffness.h>
#include <reduction/component_modes.h>
#include <reduction/reduced_body_builder.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <sstream>

using namespace flextrack;
using namespace flextrack::multibody;
using namespace flextrack::multibody::test;
using dealii::FullMatrix;
using dealii::Vector;

namespace
{
/// A steel-like straight cantilever along x, clamped at s = 0 (the body frame), output point
/// "tip" at s = L: L = 1 m, E = 2.1e11 Pa, I = 1e-9 m^4 (E I = 210 N m^2), A = 1e-4 m^2,
/// rho = 7800 kg/m^3 (q = rho A g = 7.65 N/m under g = 9.81 m/s^2). Slenderness L / sqrt(I / A) =
/// 316: shear deflection q L^2 / (2 kappa G A) ~ 6e-7 m, 1e-4 of the bending deflection.
/// Craig-Bampton, 20 cubic elements, @p normal_modes fixed-interface modes.
std::shared_ptr<const reduction::ReducedBody> cantilever(const unsigned int normal_modes)
{
  std::ostringstream t;
  t << "set Model = body\nsubsection Body\n set Solid = false\n set Arms = beam\n"
    << " set Output points = tip: arm beam at 1\nend\n"
    << "subsection Arm beam\n subsection Curve\n  set Kind = line\n  subsection Line\n   set Start point = 0, 0, 0\n"
    << "   set End point = 1, 0, 0\n  end\n end\n"
    << " subsection Cross section\n  set Shape = explicit\n  set Area = 1e-4\n  set Iy = 1e-9\n  set Iz = 1e-9\n"
    << "  set Torsion constant = 2e-9\n end\n"
    << " subsection Material\n  set Young's modulus = 2.1e11\n  set Density = 7800\n end\n"
    << " subsection Supports\n  set Start = clamped\n end\n"
    << " subsection Mesh\n  set Number of elements = 20\n  set Element degree = 3\n end\nend\n"
    << "subsection Reduction\n set Method = craig bampton\n set Number of normal modes = " << normal_modes << "\nend\n";
  const auto scene = io::read_body_scene_from_string(t.str());
  const fem::BodyModel model(scene.body);
  return std::make_shared<reduction::ReducedBody>(
    reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), scene.reduction.method_name()));
}

constexpr double E = 2.1e11, I = 1e-9, A = 1e-4, rho = 7800, L = 1, g = 9.81;

/// The cantilever clamped to the ground by a fixed joint at its root, gravity -z.
void build_cantilever(System &s, const std::shared_ptr<const reduction::ReducedBody> &beam)
{
  FlexibleOptions o;
  o.geometric_stiffening = false; // the closed form is linear; a transverse load gives no axial prestress
  s.add_body(std::make_unique<FloatingBody>("beam", beam, o, InitialState()));
  add_joint(s, "fixed", "clamp", "beam", "ground", Vector3(), Vector3({0, 0, 1}));
  s.finalize();
}

/// Tip displacement along global z [m] (the frame stays put: clamped) and its rate [m/s].
double tip(const System &s, const reduction::ReducedBody &beam, const Vector<double> &y, const bool velocity = false)
{
  const FullMatrix<double> &phi = beam.output_points.at(0).modes;
  const unsigned int first = velocity ? s.n_q() + s.v_offset(1) + 6 : s.q_offset(1) + 7;
  double w = 0;
  for (unsigned int k = 0; k < beam.n_modes(); ++k) w += phi(2, k) * y[first + k];
  return w;
}

struct Motion
{
  double tip_velocity = 0, modal_velocity = 0, tip_min = 1e300, tip_max = -1e300; ///< over the run
};

Motion run(System &s, const reduction::ReducedBody &beam, const Vector<double> &y0, const Vector<double> &yp0, const double t_end)
{
  Motion m;
  IdaIntegrator ida(s, tight(1e-8, 1e-12));
  ida.initialize(0, y0, yp0);
  ida.integrate(t_end, 1e-3, [&](double, const Vector<double> &y, const Vector<double> &) {
    m.tip_velocity = std::max(m.tip_velocity, std::abs(tip(s, beam, y, true)));
    for (unsigned int k = 0; k < beam.n_modes(); ++k)
      m.modal_velocity = std::max(m.modal_velocity, std::abs(y[s.n_q() + s.v_offset(1) + 6 + k]));
    m.tip_min = std::min(m.tip_min, tip(s, beam, y));
    m.tip_max = std::max(m.tip_max, tip(s, beam, y));
  });
  return m;
}
} // namespace

TEST(MultibodyEquilibrium, cantilever_sags_by_closed_form_and_stays_at_rest)
{
  const double q = rho * A * g, reference = -q * std::pow(L, 4) / (8 * E * I); // Euler-Bernoulli: -4.555e-3 m
  double previous_error = 1e300;
  for (const unsigned int modes : {4u, 12u})
    {
      const auto beam = cantilever(modes);
      System s(Vector3({0, 0, -g}));
      build_cantilever(s, beam);
      Vector<double> y, yp;
      InitialConditionSettings settings;
      settings.static_equilibrium = true;
      const auto report = consistent_initial_conditions(s, 0, y, yp, settings);
      std::cout << report.text();
      const double w = tip(s, *beam, y), error = std::abs(w / reference - 1);
      std::cout << "  " << modes << " normal modes: static tip deflection " << w << " m, closed form " << reference
                << " m, relative error " << error << "\n";
      ASSERT_TRUE(report.equilibrium.solved);
      EXPECT_TRUE(report.equilibrium.stable);
      // The error is the basis error (the uniform load's static shape by a few fixed-interface
      // modes) plus shear deformation (1.2e-4, see cantilever()). 12 modes (about 5 flapwise
      // bending modes in the basis): measured 1.19e-4; bound 1e-3. 4 modes: measured 7.9e-4, bound 1e-2.
      EXPECT_LT(error, modes == 12 ? 1e-3 : 1e-2);
      EXPECT_LT(error, previous_error); // converges as modes are added
      previous_error = error;
      EXPECT_LE(report.equilibrium.iterations, 5u); // linear structure: one Newton step, one check
      EXPECT_NEAR(report.equilibrium.moves.at(0).displacement, 0, 1e-12); // the clamp holds the frame
      if (modes != 12) continue;

      // Started from the equilibrium the beam stays there: the only motion is the integrator's
      // error (rtol 1e-8) and the equilibrium's residual (1e-10 of the weight); measured
      // |v_tip| 5e-15 m/s. Started straight (as given) it swings between 0 and twice the static
      // deflection with |v_tip| ~ omega_1 |w| = 57.7 rad/s * 4.55e-3 m = 0.26 m/s.
      const Motion rest = run(s, *beam, y, yp, 0.3);
      std::cout << "  from equilibrium: max |v_tip| " << rest.tip_velocity << " m/s, max |eta'| " << rest.modal_velocity
                << ", tip in [" << rest.tip_min << ", " << rest.tip_max << "] m\n";
      EXPECT_LT(rest.tip_velocity, 1e-6 * 0.26);
      EXPECT_LT(rest.tip_max - rest.tip_min, 1e-6 * std::abs(reference));

      System s2(Vector3({0, 0, -g}));
      build_cantilever(s2, beam);
      Vector<double> y2, yp2;
      consistent_initial_conditions(s2, 0, y2, yp2);
      const Motion swing = run(s2, *beam, y2, yp2, 0.3);
      std::cout << "  as given: max |v_tip| " << swing.tip_velocity << " m/s, tip in [" << swing.tip_min << ", "
                << swing.tip_max << "] m\n";
      EXPECT_GT(swing.tip_velocity, 0.2);
      EXPECT_NEAR(swing.tip_min, 2 * reference, 0.05 * std::abs(reference)); // undamped: overshoots to 2 w_static
    }
}

TEST(MultibodyEquilibrium, pendulum_returns_to_rest_and_inverted_one_is_called_unstable)
{
  // Compound pendulum: m = 1.5 kg at L = 0.8 m from a revolute joint at the origin (axis z),
  // gravity -y. Equilibria: hanging (stable) and upright (unstable).
  for (const double start_deg : {60.0, 150.0})
    {
      const double th = start_deg * M_PI / 180, Lp = 0.8;
      System s(Vector3({0, -9.81, 0}));
      add_rigid(s, "bob", 1.5, diagonal(0.02, 0.02, 0.02), Vector3({Lp * std::sin(th), -Lp * std::cos(th), 0}),
                geometry::euler_parameters_from_rotation_vector(Vector3({0, 0, th})));
      add_joint(s, "revolute", "pivot", "bob", "ground", Vector3(), Vector3({0, 0, 1}));
      s.finalize();
      Vector<double> y, yp;
      InitialConditionSettings settings;
      settings.static_equilibrium = true;
      const auto report = consistent_initial_conditions(s, 0, y, yp, settings);
      std::cout << report.text();
      const bool hanging = start_deg < 90;
      // Newton goes to the nearer equilibrium: 60 deg -> hanging (turned 60 deg), 150 deg ->
      // upright (30 deg). Positions to the equilibrium tolerance (1e-10 of the weight).
      EXPECT_NEAR(y[0], 0, 1e-9);
      EXPECT_NEAR(y[1], hanging ? -Lp : Lp, 1e-9);
      EXPECT_NEAR(report.equilibrium.moves.at(0).rotation, hanging ? th : M_PI - th, 1e-9);
      EXPECT_EQ(report.equilibrium.stable, hanging);
      for (unsigned int i = 0; i < s.n_v(); ++i) EXPECT_EQ(y[s.n_q() + i], 0.0); // at rest
    }
}

TEST(MultibodyEquilibrium, mechanism_under_the_loads_is_refused_naming_the_free_motion)
{
  // A slider on a level guide along x under gravity -y: any x is an equilibrium.
  System s(Vector3({0, -9.81, 0}));
  add_rigid(s, "slider", 2.0, diagonal(1e-3, 1e-3, 1e-3), Vector3({0.4, 0, 0}));
  add_joint(s, "prismatic", "guide", "slider", "ground", Vector3({0.4, 0, 0}), Vector3({1, 0, 0}), "", Vector3({0, 1, 0}));
  s.finalize();
  Vector<double> y, yp;
  InitialConditionSettings settings;
  settings.static_equilibrium = true;
  try
    {
      consistent_initial_conditions(s, 0, y, yp, settings);
      FAIL() << "a mechanism was accepted";
    }
  catch (const InputError &e)
    {
      const std::string m = e.what();
      std::cout << m << "\n";
      EXPECT_NE(m.find("Initial state"), std::string::npos);
      EXPECT_NE(m.find("mechanism"), std::string::npos);
      EXPECT_NE(m.find("body slider, R'_x"), std::string::npos);
    }
}

TEST(MultibodyEquilibrium, load_beyond_what_the_structure_holds_is_refused_naming_the_residual)
{
  // The pendulum of the test above with a torque of 2 m g L about the pivot: no equilibrium.
  System s(Vector3({0, -9.81, 0}));
  add_rigid(s, "bob", 1.5, diagonal(0.02, 0.02, 0.02), Vector3({0, -0.8, 0}));
  add_joint(s, "revolute", "pivot", "bob", "ground", Vector3(), Vector3({0, 0, 1}));
  dealii::ParameterHandler prm;
  declare_force_parameters(prm);
  prm.set("Kind", "applied load");
  prm.set("Body 1", "bob");
  prm.set("Position 1", "0, -0.8, 0");
  prm.set("Torque", "0; 0; " + std::to_string(2 * 1.5 * 9.81 * 0.8));
  s.add_force(create_force("torque", prm, s.body_lookup()));
  s.finalize();
  Vector<double> y, yp;
  InitialConditionSettings settings;
  settings.static_equilibrium = true;
  try
    {
      consistent_initial_conditions(s, 0, y, yp, settings);
      FAIL() << "an equilibrium was reported where there is none";
    }
  catch (const InputError &e)
    {
      const std::string m = e.what();
      std::cout << m << "\n";
      EXPECT_NE(m.find("Initial state"), std::string::npos);
      EXPECT_NE(m.find("no equilibrium found"), std::string::npos); // names the worst residual component
      EXPECT_NE(m.find("joint pivot"), std::string::npos);
    }
}

// The tangent of the static equilibrium iteration is taken from the DAE Jacobian (analytic
// bodies, joints and forces differenced over their own columns; multibody/static_stiffness.h).
// Oracle: central differences of the static residual over every velocity coordinate, step
// 1e-6 (truncation O(h^2) and rounding O(eps / h), both about 1e-10 relative). Tolerance: 1e-6
// of the largest entry, as the element Jacobian tests allow for differenced blocks.
TEST(MultibodyEquilibrium, static_stiffness_from_the_dae_jacobian_equals_differences)
{
  auto check = [](System &s, const Vector<double> &y, const Vector<double> &lambda, const std::string &what) {
    FullMatrix<double> K, K_diff, B, B_diff;
    static_stiffness(s, 0.0, y, lambda, K, B);
    static_stiffness_by_differences(s, 0.0, y, lambda, 1e-6, K_diff, B_diff);
    ASSERT_EQ(K.m(), s.n_v());
    double largest = 0, deviation = 0;
    for (unsigned int i = 0; i < K.m(); ++i)
      for (unsigned int j = 0; j < K.n(); ++j)
        {
          largest = std::max(largest, std::abs(K_diff(i, j)));
          deviation = std::max(deviation, std::abs(K(i, j) - K_diff(i, j)));
        }
    std::cout << what << ": largest entry " << largest << ", largest deviation " << deviation << "\n";
    EXPECT_GT(largest, 0.0);
    EXPECT_LE(deviation, 1e-6 * largest) << what;
  };
  {
    // A flexible cantilever on a fixed joint, bent and turned, with multipliers far from balance.
    const auto beam = cantilever(4);
    System s(Vector3({0, 0, -g}));
    build_cantilever(s, beam);
    Vector<double> y, lambda(s.n_lambda());
    s.initial_guess(y);
    const unsigned int q = s.q_offset(1);
    const auto p = geometry::euler_parameters_from_rotation_vector(Vector3({0.2, -0.1, 0.3}));
    for (unsigned int i = 0; i < 4; ++i) y[q + 3 + i] = p[i];
    y[q] = 0.01, y[q + 1] = -0.02, y[q + 2] = 0.005;
    for (unsigned int k = 0; k < beam->n_modes(); ++k) y[q + 7 + k] = 1e-3 * std::cos(1.0 + k);
    for (unsigned int k = 0; k < lambda.size(); ++k) lambda[k] = 10.0 * std::sin(2.0 + k);
    check(s, y, lambda, "flexible cantilever on a fixed joint");
  }
  {
    // A rigid double pendulum (revolute joints about z) off its rest position, a spherical
    // joint's worth of multipliers on each pin.
    System s(Vector3({0, -9.81, 0}));
    add_rigid(s, "upper", 1.5, diagonal(0.02, 0.03, 0.04), Vector3({0.3, -0.2, 0}),
              geometry::euler_parameters_from_rotation_vector(Vector3({0, 0, 0.9})));
    add_rigid(s, "lower", 0.7, diagonal(0.01, 0.01, 0.02), Vector3({0.8, -0.5, 0}),
              geometry::euler_parameters_from_rotation_vector(Vector3({0, 0, 1.4})));
    add_joint(s, "revolute", "top", "upper", "ground", Vector3(), Vector3({0, 0, 1}));
    add_joint(s, "revolute", "middle", "lower", "upper", Vector3({0.6, -0.4, 0}), Vector3({0, 0, 1}));
    s.finalize();
    Vector<double> y, lambda(s.n_lambda());
    s.initial_guess(y);
    for (unsigned int k = 0; k < lambda.size(); ++k) lambda[k] = 5.0 * std::cos(0.5 + k);
    check(s, y, lambda, "rigid double pendulum");
  }
}
