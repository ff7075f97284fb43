// Rigid multibody systems against closed forms (issue 9, acceptance): the torque-free asymmetric
// body (conservation; stability of spin about the principal axes), the large-amplitude pendulum
// (period from the complete elliptic integral), the slider-crank with a driven crank (closed-form
// slider position) and the four-bar linkage (redundant in 3D: runs, dropped equations named).
#include "multibody_test_helpers.h"

#include <base/input_error.h>
#include <multibody/linearization.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace flextrack;
using namespace flextrack::multibody;
using namespace flextrack::multibody::test;
using dealii::Vector;

namespace
{
/// Energy and angular momentum of body 1.
void invariants(const System &s, const Vector<double> &y, double &energy, Vector3 &L)
{
  Vector3 P;
  s.body(1).momentum(s.q_of(1, y), s.v_of(1, y), P, L);
  energy = s.body(1).kinetic_energy(s.q_of(1, y), s.v_of(1, y));
}

/// The torque-free asymmetric body of the conservation tests: 2 kg, J = diag(1, 2, 3) kg m^2,
/// omega = (0.5, 0.2, 1.5) rad/s, turned and moving.
void add_torque_free_top(System &s)
{
  add_rigid(s, "top", 2.0, diagonal(1, 2, 3), Vector3({1, 2, 3}),
            geometry::euler_parameters_from_rotation_vector(Vector3({0.3, -0.2, 0.5})), Vector3({0.1, 0, -0.2}),
            Vector3({0.5, 0.2, 1.5}));
}

/// Largest angle [rad] between the body axis @p axis and the angular momentum, over @p t_end.
double largest_wobble(const unsigned int axis, const double t_end)
{
  System s;
  const Vector3 w0 = axis == 0 ? Vector3({2, 1e-3, 1e-3}) : axis == 1 ? Vector3({1e-3, 2, 1e-3}) : Vector3({1e-3, 1e-3, 2});
  add_rigid(s, "top", 1.0, diagonal(1, 2, 3), Vector3(), {{1, 0, 0, 0}}, Vector3(), w0);
  s.finalize();
  Vector<double> y, yp;
  consistent_initial_conditions(s, 0, y, yp);
  IdaIntegrator ida(s, tight(1e-8, 1e-10));
  ida.initialize(0, y, yp);
  double e0;
  Vector3 L0;
  invariants(s, y, e0, L0);
  double worst = 0;
  ida.integrate(t_end, 0.1, [&](double, const Vector<double> &yy, const Vector<double> &) {
    const Matrix3 A = geometry::rotation_matrix({{yy[3], yy[4], yy[5], yy[6]}});
    Vector3 e;
    for (unsigned int a = 0; a < 3; ++a) e[a] = A[a][axis];
    worst = std::max(worst, std::acos(std::min(1.0, std::abs(e * L0) / L0.norm())));
  });
  return worst;
}

} // namespace

namespace
{
/// The torque-free body run for 100 s with @p settings: the largest relative drifts of its
/// kinetic energy and angular momentum and of |p|^2 over the output rows (every 1 s).
struct Drift
{
  double energy = 0, momentum = 0, normalisation = 0;
  IntegratorStatistics statistics;
};

Drift torque_free_drift(const IntegratorSettings &settings)
{
  System s;
  add_torque_free_top(s);
  s.finalize();
  Vector<double> y, yp;
  consistent_initial_conditions(s, 0, y, yp);
  double e0, e;
  Vector3 L0, L;
  invariants(s, y, e0, L0);
  const auto integrator = make_integrator(s, settings);
  integrator->initialize(0, y, yp);
  Drift d;
  integrator->integrate(100, 1.0, [&](double, const Vector<double> &yy, const Vector<double> &) {
    invariants(s, yy, e, L);
    d.energy = std::max(d.energy, std::abs(e - e0) / e0);
    d.momentum = std::max(d.momentum, (L - L0).norm() / L0.norm());
    d.normalisation = std::max(d.normalisation, std::abs(yy[3] * yy[3] + yy[4] * yy[4] + yy[5] * yy[5] + yy[6] * yy[6] - 1));
  });
  d.statistics = integrator->statistics();
  return d;
}
} // namespace

TEST(MultibodyRigid, torque_free_body_conserves_energy_and_angular_momentum)
{
  // J = diag(1, 2, 3) kg m^2, omega = (0.5, 0.2, 1.5) rad/s: no force, so the kinetic energy and
  // the angular momentum (global) are constants of the exact motion. Reference: those invariants
  // at t = 0; tolerance 1e-8 relative over 100 s at rtol 1e-10 (issue 9).
  const Drift d = torque_free_drift(tight(1e-10, 1e-12));
  std::cout << "  torque-free body: max relative energy error " << d.energy << ", angular momentum " << d.momentum
            << "; " << d.statistics.steps << " steps, " << d.statistics.error_test_failures << " error-test failures, "
            << d.statistics.jacobian_evaluations << " Jacobians\n";
  EXPECT_LT(d.energy, 1e-8);
  EXPECT_LT(d.momentum, 1e-8);
}

TEST(MultibodyRigid, spin_about_intermediate_axis_is_unstable)
{
  // Euler's equations: spin about the axis of the largest or smallest moment is stable, about the
  // intermediate one unstable (growth rate w sqrt((J2-J1)(J3-J2)/(J1 J3)) = 1.15 /s here). A 1e-3
  // rad/s perturbation stays below 0.01 rad of wobble for the stable axes over 30 s, and grows
  // to a flip (> 1 rad) for the intermediate axis.
  const double wobble_x = largest_wobble(0, 30), wobble_y = largest_wobble(1, 30), wobble_z = largest_wobble(2, 30);
  std::cout << "  wobble over 30 s: about x " << wobble_x << " rad, y " << wobble_y << " rad, z " << wobble_z << " rad\n";
  EXPECT_LT(wobble_x, 0.01);
  EXPECT_GT(wobble_y, 1.0);
  EXPECT_LT(wobble_z, 0.01);
}

TEST(MultibodyRigid, large_amplitude_pendulum_period_matches_elliptic_integral)
{
  // Compound pendulum: m = 1.5 kg, centre of mass at L = 0.8 m from the pivot, J_c = 0.02 kg m^2,
  // released at rest from 150 deg. theta'' = -(m g L / I_p) sin theta with I_p = m L^2 + J_c:
  // period 4 sqrt(I_p / (m g L)) K(sin(theta0 / 2)), K by the arithmetic-geometric mean
  // K(k) = pi / (2 agm(1, sqrt(1 - k^2))) (add_large_amplitude_pendulum). Tolerance 1e-8
  // relative (issue 9).
  System s(Vector3({0, -9.81, 0}));
  const double period = add_large_amplitude_pendulum(s);
  s.finalize();
  Vector<double> y, yp;
  const auto report = consistent_initial_conditions(s, 0, y, yp);
  EXPECT_LT(report.corrections[0].displacement, 1e-12); // assembled as given

  IdaIntegrator ida(s, tight(1e-11, 1e-13));
  const unsigned int omega_z = s.n_q() + 5;
  ida.set_root_functions(1, [&](double, const Vector<double> &yy, const Vector<double> &, double *r) { r[0] = yy[omega_z]; });
  ida.initialize(0, y, yp);
  std::vector<double> turning_points;
  double t = 0;
  while (turning_points.size() < 2 && t < 20)
    {
      t = ida.integrate(20, 0, nullptr);
      if (!ida.roots_found().empty() && ida.roots_found()[0] != 0) turning_points.push_back(t);
    }
  ASSERT_EQ(turning_points.size(), 2u);
  std::cout << "  pendulum period " << std::setprecision(12) << turning_points[1] << " s, closed form " << period
            << " s, relative error " << std::abs(turning_points[1] - period) / period << "\n";
  EXPECT_NEAR(turning_points[1], period, 1e-8 * period);
  EXPECT_NEAR(turning_points[0], period / 2, 1e-8 * period);
}

TEST(MultibodyRigid, driven_slider_crank_follows_closed_form)
{
  // Crank r = 0.1 m driven at 2 pi rad/s about z, rod l = 0.3 m, slider on a prismatic joint
  // along x; revolute joints at both ends of the rod (a planar loop: 3 equations redundant in 3D).
  // Slider position x = r cos th + sqrt(l^2 - r^2 sin^2 th): tolerance 1e-8 m.
  const double r = 0.1, l = 0.3;
  System s(Vector3({0, -9.81, 0}));
  add_rigid(s, "crank", 0.5, diagonal(1e-4, 5e-4, 5e-4), Vector3({r / 2, 0, 0}));
  add_rigid(s, "rod", 1.0, diagonal(1e-4, 8e-3, 8e-3), Vector3({r + l / 2, 0, 0}));
  add_rigid(s, "slider", 2.0, diagonal(1e-3, 1e-3, 1e-3), Vector3({r + l, 0, 0}));
  add_joint(s, "revolute", "drive", "crank", "ground", Vector3(), Vector3({0, 0, 1}), "2*pi*t");
  add_joint(s, "revolute", "crank_pin", "rod", "crank", Vector3({r, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "revolute", "wrist_pin", "slider", "rod", Vector3({r + l, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "prismatic", "guide", "slider", "ground", Vector3({r + l, 0, 0}), Vector3({1, 0, 0}));
  s.finalize();
  Vector<double> y, yp;
  const auto report = consistent_initial_conditions(s, 0, y, yp);
  std::cout << report.text();
  EXPECT_EQ(report.dropped.size(), 3u); // 21 equations, 18 coordinates, 0 degrees of freedom

  IdaIntegrator ida(s, tight(1e-10, 1e-12));
  ida.initialize(0, y, yp);
  const unsigned int slider_x = s.q_offset(3);
  double worst = 0;
  unsigned int outputs = 0;
  ida.integrate(2.0, 0.01, [&](double t, const Vector<double> &yy, const Vector<double> &) {
    const double th = 2 * M_PI * t, x = r * std::cos(th) + std::sqrt(l * l - r * r * std::sin(th) * std::sin(th));
    worst = std::max(worst, std::abs(yy[slider_x] - x));
    ++outputs;
  });
  const auto stats = ida.statistics();
  std::cout << "  slider-crank: max |x - x_exact| = " << worst << " m over " << outputs << " outputs; " << stats.steps
            << " steps, " << stats.error_test_failures << " error-test failures\n";
  EXPECT_EQ(outputs, 200u);
  EXPECT_LT(worst, 1e-8);
}

TEST(MultibodyRigid, four_bar_linkage_runs_and_names_dropped_equations)
{
  // Ground pivots A = (0,0,0), D = (2,0,0); crank AB = 1 m (B = (0,1,0)), coupler BC = 2.5 m,
  // rocker CD = 2 m; four revolute joints about z: 20 equations for 18 coordinates and one degree
  // of freedom, so 3 are dependent. The run (2 s under gravity, crank started at 1 rad/s) must
  // keep every active constraint satisfied and report the three dropped equations.
  System s(Vector3({0, -9.81, 0}));
  add_planar_four_bar(s);
  Vector<double> y, yp;
  const auto report = consistent_initial_conditions(s, 0, y, yp);
  std::cout << report.text();
  ASSERT_EQ(report.dropped.size(), 3u);
  const std::string text = report.text();
  EXPECT_NE(text.find("redundant: joint D"), std::string::npos); // the last joint closes the loop
  EXPECT_LT(report.velocity_residual, 1e-10);

  IdaIntegrator ida(s, tight(1e-8, 1e-10));
  ida.initialize(0, y, yp);
  double worst = 0;
  ida.integrate(2.0, 0.05, [&](double t, const Vector<double> &yy, const Vector<double> &) {
    Vector<double> phi, phi_t;
    dealii::FullMatrix<double> Bm;
    s.constraints(t, yy, true, phi, Bm, phi_t); // all 20, dropped ones included
    worst = std::max(worst, phi.linfty_norm());
  });
  std::cout << "  four-bar: max |Phi| (all 20 equations) over 2 s: " << worst << "\n";
  EXPECT_LT(worst, 1e-7); // ~ tolerance x size; the dropped equations hold because they depend on the others
  EXPECT_NEAR(ida.time(), 2.0, 1e-12);
}

TEST(MultibodyRigid, linearized_pendulum_frequency_matches_closed_form)
{
  // Hanging compound pendulum (m = 1.5 kg, L = 0.8 m, J_c = 0.02 kg m^2) linearised at rest:
  // one mode, w = sqrt(m g L / (m L^2 + J_c)), no damping. The stiffness comes from central
  // differences (step 1e-6): tolerance 1e-7 relative.
  const double m = 1.5, L = 0.8, Jc = 0.02, g = 9.81;
  System s(Vector3({0, -g, 0}));
  add_rigid(s, "bob", m, diagonal(Jc, Jc, Jc), Vector3({0, -L, 0}));
  add_joint(s, "revolute", "pivot", "bob", "ground", Vector3(), Vector3({0, 0, 1}));
  s.finalize();
  Vector<double> y, yp;
  consistent_initial_conditions(s, 0, y, yp);
  const auto modes = linearize(s, 0, y);
  ASSERT_EQ(modes.size(), 1u);
  const double f = std::sqrt(m * g * L / (m * L * L + Jc)) / (2 * M_PI);
  std::cout << "  linearised pendulum: " << modes[0].frequency_hz << " Hz, closed form " << f << " Hz, damping ratio "
            << modes[0].damping_ratio << "\n";
  EXPECT_NEAR(modes[0].frequency_hz, f, 1e-7 * f);
  EXPECT_NEAR(modes[0].damping_ratio, 0, 1e-7);
}

TEST(MultibodyRigid, conflicting_joints_are_refused_with_their_names)
{
  // A block welded to the ground and also driven about z by a revolute driver: the driver's
  // equations depend on the weld's but prescribe a rotation: an InputError naming the driver.
  System s;
  add_rigid(s, "block", 1.0, diagonal(0.1, 0.1, 0.1), Vector3({1, 0, 0}));
  add_joint(s, "fixed", "weld", "block", "ground", Vector3({1, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "revolute", "spin", "block", "ground", Vector3({1, 0, 0}), Vector3({0, 0, 1}), "0.5*t");
  s.finalize();
  Vector<double> y, yp;
  try
    {
      consistent_initial_conditions(s, 0, y, yp);
      FAIL() << "conflicting joints accepted";
    }
  catch (const InputError &e)
    {
      std::cout << "  " << e.what() << "\n";
      EXPECT_NE(std::string(e.what()).find("'spin'"), std::string::npos);
    }
}


TEST(MultibodyRigid, generalized_alpha_torque_free_body_conserves_invariants_at_second_order)
{
  // Issue 11 acceptance: generalised-alpha (rho_inf 0.8, fixed steps 4 ms and 2 ms) on the
  // torque-free body of the test above. Reference: the kinetic energy and global angular momentum
  // at t = 0 (constants of the exact motion). A second-order method drifts by C h^2 over the run:
  // halving the step must divide the drift by 4 (observed order 2 +- 0.3), and at 2 ms the drift
  // over 100 s stays below 1e-5 relative.
  std::vector<Drift> drift;
  for (const double step : {4e-3, 2e-3})
    {
      IntegratorSettings settings = tight(1e-10, 1e-12);
      settings.method = IntegrationMethod::generalized_alpha;
      settings.step = step;
      settings.spectral_radius = 0.8;
      drift.push_back(torque_free_drift(settings));
      const Drift &d = drift.back();
      std::cout << "  generalised-alpha, step " << step << " s: max relative energy drift " << d.energy
                << ", angular momentum " << d.momentum << ", | |p|^2 - 1 | " << d.normalisation << "; "
                << d.statistics.jacobian_evaluations << " Jacobians\n";
      // The normalisation is an equation of every step: it holds to the Newton tolerance (rtol 1e-10).
      EXPECT_LT(d.normalisation, 1e-10);
    }
  const double order_energy = std::log2(drift[0].energy / drift[1].energy),
               order_momentum = std::log2(drift[0].momentum / drift[1].momentum);
  std::cout << "  observed order: energy " << order_energy << ", angular momentum " << order_momentum << "\n";
  EXPECT_NEAR(order_energy, 2.0, 0.3);
  EXPECT_NEAR(order_momentum, 2.0, 0.3);
  EXPECT_LT(drift[1].energy, 1e-5);
  EXPECT_LT(drift[1].momentum, 1e-5);
}

TEST(MultibodyRigid, generalized_alpha_adaptive_step_follows_its_tolerance)
{
  // Generalised-alpha with 'Adaptive step' on the torque-free body (100 s). Reference: the
  // invariants at t = 0 (constants of the exact motion). A second-order method whose local error
  // (O(h^3)) is held at the tolerance has a global error proportional to tol^(2/3): tightening
  // rtol from 1e-5 to 1e-8 must shrink the drift by 1000^(2/3) = 100, within a factor 10 either
  // way (the estimate's constant and the rejected steps); measured 110.
  std::vector<Drift> drift;
  for (const double rtol : {1e-5, 1e-8})
    {
      IntegratorSettings settings = tight(rtol, rtol * 1e-2);
      settings.method = IntegrationMethod::generalized_alpha;
      settings.adaptive_step = true;
      settings.step = 1e-3;
      drift.push_back(torque_free_drift(settings));
      const Drift &d = drift.back();
      std::cout << "  adaptive generalised-alpha, rtol " << rtol << ": drift of the invariants "
                << std::max(d.energy, d.momentum) << ", " << d.statistics.steps << " steps ("
                << d.statistics.error_test_failures << " rejected)\n";
    }
  const double ratio = std::max(drift[0].energy, drift[0].momentum) / std::max(drift[1].energy, drift[1].momentum);
  EXPECT_GT(ratio, 10.0);
  EXPECT_LT(ratio, 1000.0);
  EXPECT_GT(drift[1].statistics.steps, drift[0].statistics.steps); // a tighter tolerance takes smaller steps
}
