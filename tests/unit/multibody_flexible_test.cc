// Flexible bodies in the multibody engine (issue 9, acceptance): a free-floating reduced body set
// vibrating and spinning conserves linear and angular momentum (1e-9 relative) and, without
// damping and geometric stiffening, energy (to the integrator tolerance); the rigid twin has the
// same mass properties; the Jacobian with a flexible body (geometric stiffening on) against
// central differences of the residual.
#include "multibody_test_helpers.h"

#include <fem/body_model.h>
#include <io/body_scene.h>
#include <multibody/monitors.h>
#include <reduction/component_modes.h>
#include <reduction/reduced_body_builder.h>

#include <Epetra_CrsMatrix.h>

#include <gtest/gtest.h>

#include <iostream>
#include <random>

using namespace flextrack;
using namespace flextrack::multibody;
using namespace flextrack::multibody::test;
using dealii::FullMatrix;
using dealii::Vector;

namespace
{
/// A free steel rod, 1 m along x, 20 mm square, free-interface basis (4 normal modes + the
/// residual attachment modes of its end interface), geometric stiffness of inertial loads.
std::shared_ptr<const reduction::ReducedBody> free_rod()
{
  static std::shared_ptr<const reduction::ReducedBody> body;
  if (body) return body;
  const std::string text =
    "set Model = body\nsubsection Body\n set Solid = false\n set Arms = rod\n set Interfaces = tip: arm rod at 1\nend\n"
    "subsection Arm rod\n subsection Curve\n  set Kind = line\n  subsection Line\n   set Start point = 0, 0, 0\n"
    "   set End point = 1, 0, 0\n  end\n end\n subsection Cross section\n  set Shape = rectangle\n  set Width = 0.02\n"
    "  set Height = 0.02\n end\n subsection Supports\n  set Start = free\n end\n subsection Mesh\n"
    "  set Number of elements = 6\n end\nend\nsubsection Reduction\n set Method = free interface\n"
    " set Number of normal modes = 4\n set Geometric stiffness = true\nend\n";
  const auto scene = io::read_body_scene_from_string(text);
  const fem::BodyModel model(scene.body);
  body = std::make_shared<reduction::ReducedBody>(
    reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), scene.reduction.method_name()));
  return body;
}

InitialState vibrating_and_spinning(const unsigned int n)
{
  InitialState s;
  s.position = Vector3({0.2, -0.1, 0.3});
  s.orientation = geometry::euler_parameters_from_rotation_vector(Vector3({0.1, 0.4, -0.2}));
  s.velocity = Vector3({0.3, 0.1, -0.2});
  s.angular_velocity = Vector3({0.5, 1.0, 2.0});
  s.modal.reinit(n);
  s.modal_velocity.reinit(n);
  for (unsigned int k = 0; k < n; ++k) s.modal_velocity[k] = 0.02 / (1 + k); // [modal units/s]
  return s;
}

struct Drift
{
  double momentum = 0, angular_momentum = 0, energy = 0;
};

Drift run_free_rod(const bool stiffening, const double t_end, const double rtol)
{
  const auto rod = free_rod();
  System s;
  FlexibleOptions o;
  o.geometric_stiffening = stiffening;
  s.add_body(std::make_unique<FloatingBody>("rod", rod, o, vibrating_and_spinning(rod->n_modes())));
  s.finalize();
  Vector<double> y, yp;
  consistent_initial_conditions(s, 0, y, yp);
  Monitors monitors(s);
  IdaIntegrator ida(s, tight(rtol, rtol * 1e-2));
  ida.initialize(0, y, yp);
  monitors.attach(ida);
  Vector3 P0, L0, P, L;
  s.body(1).momentum(s.q_of(1, y), s.v_of(1, y), P0, L0);
  const MonitorValues m0 = monitors.evaluate(0, y);
  EnergyBalance balance(m0);
  Drift d;
  ida.integrate(t_end, t_end / 50, [&](double t, const Vector<double> &yy, const Vector<double> &) {
    s.body(1).momentum(s.q_of(1, yy), s.v_of(1, yy), P, L);
    d.momentum = std::max(d.momentum, (P - P0).norm() / P0.norm());
    d.angular_momentum = std::max(d.angular_momentum, (L - L0).norm() / L0.norm());
    d.energy = std::max(d.energy, std::abs(balance.error(monitors.evaluate(t, yy))));
  });
  const auto st = ida.statistics();
  std::cout << "  free rod (" << rod->n_modes() << " modes, stiffening " << (stiffening ? "on" : "off") << ", rtol "
            << rtol << "): momentum drift " << d.momentum << ", angular momentum " << d.angular_momentum
            << ", energy " << d.energy << "; " << st.steps << " steps, " << st.error_test_failures
            << " error-test failures, " << st.jacobian_evaluations << " Jacobians\n";
  return d;
}
} // namespace

TEST(MultibodyFlexible, rigid_twin_has_the_same_mass_properties)
{
  // The mass matrix of the body made rigid equals the rigid-body block (R, omega) of the flexible
  // one at eta = 0 (same m, s, J_O): exact, 1e-14 relative.
  const auto rod = free_rod();
  FlexibleOptions rigid;
  rigid.make_rigid = true;
  const FloatingBody flexible("f", rod, FlexibleOptions(), InitialState()), twin("r", rod, rigid, InitialState());
  EXPECT_EQ(twin.n_modes(), 0u);
  std::vector<double> q(flexible.n_q()), v(flexible.n_v()), qr(twin.n_q()), vr(twin.n_v());
  flexible.initial_coordinates(q.data(), v.data());
  twin.initial_coordinates(qr.data(), vr.data());
  FullMatrix<double> M, Mr;
  flexible.mass_matrix(q.data(), M);
  twin.mass_matrix(qr.data(), Mr);
  for (unsigned int i = 0; i < 6; ++i)
    for (unsigned int k = 0; k < 6; ++k) EXPECT_NEAR(Mr(i, k), M(i, k), 1e-14 * M(0, 0));
}

TEST(MultibodyFlexible, free_floating_body_conserves_momentum_with_geometric_stiffening)
{
  // No external force: linear and angular momentum are exact invariants (the elastic and
  // geometric-stiffness forces act on the modal coordinates only). Reference: their values at
  // t = 0; tolerance 1e-9 relative (issue 9), at rtol 1e-11: the drift is the integrator's error,
  // about 10 rtol (at rtol 1e-10 it measured 9.2e-10 with Amesos' KLU and 1.16e-9 with
  // SuiteSparse's, rounding alone deciding; at 1e-11: 4.3e-11 and angular 1.9e-10).
  const Drift d = run_free_rod(true, 0.2, 1e-11);
  EXPECT_LT(d.momentum, 1e-9);
  EXPECT_LT(d.angular_momentum, 1e-9);
}

TEST(MultibodyFlexible, free_floating_body_conserves_energy_without_damping)
{
  // Without damping and without geometric stiffening (a linearised, non-conservative force) the
  // energy (kinetic + strain) is an invariant. BDF damps the ~100-1000 Hz modes slightly, so the
  // drift scales with the tolerance: 1e-6 relative at rtol 1e-9, and ten times less at 1e-10.
  // Momentum is an exact invariant: its drift is the integrator's error, about 10 rtol, and falls
  // with the tolerance. At rtol 1e-10 the summation order of the linear solves alone moves it
  // between 4.5e-10 and 1.12e-9 (2026-12-03: the same Newton matrix factorised whole, condensed,
  // and condensed with its complement formed in another order; 9.2e-10 and 1.16e-9 with two KLU
  // builds before), so the bound is 20 rtol; the other test holds 1e-9 at rtol 1e-11.
  const Drift coarse = run_free_rod(false, 0.2, 1e-9), fine = run_free_rod(false, 0.2, 1e-10);
  EXPECT_LT(coarse.energy, 1e-6);
  EXPECT_LT(fine.energy, coarse.energy);
  EXPECT_LT(fine.momentum, 2e-9);
  EXPECT_LT(fine.angular_momentum, 2e-9);
  EXPECT_LT(fine.momentum, coarse.momentum);
  EXPECT_LT(fine.angular_momentum, coarse.angular_momentum);
}

namespace
{
/// A flexible rod hinged to the ground at its tip interface (revolute), under gravity, geometric
/// stiffening on, at a random inconsistent state (y, yp).
void hinged_rod_off_its_solution(System &s, Vector<double> &y, Vector<double> &yp)
{
  const auto rod = free_rod();
  s.add_body(std::make_unique<FloatingBody>("rod", rod, FlexibleOptions(), vibrating_and_spinning(rod->n_modes())));
  std::vector<double> q(s.body(1).n_q()), v(s.body(1).n_v());
  s.body(1).initial_coordinates(q.data(), v.data());
  const Matrix3 A = geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}});
  const Vector3 tip = Vector3({q[0], q[1], q[2]}) + A * Vector3({1, 0, 0});
  dealii::ParameterHandler prm;
  declare_joint_parameters(prm);
  prm.set("Kind", "revolute");
  prm.set("Body 1", "rod");
  prm.set("Position", vec(tip));
  prm.set("Axis", "0, 1, 0");
  prm.set("Interface 1", "tip");
  s.add_joint(create_joint("hinge", prm, s.body_lookup()));
  s.finalize();
  s.initial_guess(y);
  yp.reinit(y.size());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (unsigned int i = 0; i < y.size(); ++i) y[i] += 0.01 * u(rng), yp[i] = 0.3 * u(rng);
}
} // namespace

TEST(MultibodyFlexible, jacobian_with_flexible_body_matches_central_differences)
{
  // Reference: central differences of the whole residual (h = 1e-6 (1 + |y|)); tolerance 1e-7
  // relative to the largest entry.
  System s(Vector3({0, 0, -9.81}));
  Vector<double> y, yp;
  hinged_rod_off_its_solution(s, y, yp);
  const double t = 0.1, alpha = 50;
  s.assemble_jacobian(t, alpha, y, yp);
  Vector<double> Fp, Fm;
  double worst = 0, largest = 0;
  std::vector<double> values(y.size());
  std::vector<int> cols(y.size());
  for (unsigned int c = 0; c < y.size(); ++c)
    {
      const double h = 1e-6 * (1 + std::abs(y[c]));
      Vector<double> y1(y), y2(y), yp1(yp), yp2(yp);
      y1[c] += h, y2[c] -= h, yp1[c] += alpha * h, yp2[c] -= alpha * h;
      s.residual(t, y1, yp1, Fp);
      s.residual(t, y2, yp2, Fm);
      for (unsigned int r = 0; r < y.size(); ++r)
        {
          int n = 0;
          s.jacobian().ExtractGlobalRowCopy(r, values.size(), n, values.data(), cols.data());
          double a = 0;
          for (int k = 0; k < n; ++k)
            if (cols[k] == int(c)) a = values[k];
          const double fd = (Fp[r] - Fm[r]) / (2 * h);
          largest = std::max(largest, std::abs(fd));
          worst = std::max(worst, std::abs(fd - a));
        }
    }
  std::cout << "  flexible Jacobian " << y.size() << " x " << y.size() << ": max |J - J_fd| = " << worst
            << ", max |J_fd| = " << largest << "\n";
  EXPECT_LT(worst, 1e-7 * largest);
}

TEST(MultibodyFlexible, jacobian_parts_in_y_and_y_prime_match_central_differences)
{
  // System::assemble_jacobian_parts (Radau IIA's J = dF/dy and M = dF/dy' in one pass) against
  // central differences of the whole residual in y alone (h = 1e-6 (1 + |y|)) and in y' alone;
  // tolerance 1e-7 relative to each matrix' largest entry, as for the whole Jacobian above.
  // F is affine in y' (M(q) v', geometric stiffening linear in the frame accelerations), so a
  // central difference in y' is exact but for rounding, which at h = 1e-6 is 3e-4 here (elastic
  // forces of about 3e6 in the residual: eps 3e6 / h); h = 1e-2 (1 + |y'|) brings it to 1e-8, and
  // a term cubic or higher in y' would show as truncation error. Also, M must equal the
  // difference of the whole Jacobian at alpha = 1 and 0 (the two assemblies it replaces) to
  // rounding: 1e-12 of the entries compared.
  System s(Vector3({0, 0, -9.81}));
  Vector<double> y, yp;
  hinged_rod_off_its_solution(s, y, yp);
  const double t = 0.1;
  std::vector<double> M;
  s.assemble_jacobian_parts(t, y, yp, M);
  const unsigned int n = y.size();
  ASSERT_EQ(M.size(), std::size_t(n) * n);
  for (const bool in_y_prime : {false, true})
    {
      double worst = 0, largest = 0;
      Vector<double> Fp, Fm;
      for (unsigned int c = 0; c < n; ++c)
        {
          const Vector<double> &x = in_y_prime ? yp : y;
          const double h = (in_y_prime ? 1e-2 : 1e-6) * (1 + std::abs(x[c]));
          Vector<double> y1(y), y2(y), yp1(yp), yp2(yp);
          (in_y_prime ? yp1 : y1)[c] += h;
          (in_y_prime ? yp2 : y2)[c] -= h;
          s.residual(t, y1, yp1, Fp);
          s.residual(t, y2, yp2, Fm);
          for (unsigned int r = 0; r < n; ++r)
            {
              const double fd = (Fp[r] - Fm[r]) / (2 * h);
              const double a = in_y_prime ? M[std::size_t(c) * n + r] : matrix_entry(s.jacobian(), r, c);
              largest = std::max(largest, std::abs(fd));
              worst = std::max(worst, std::abs(fd - a));
            }
        }
      std::cout << "  " << (in_y_prime ? "dF/dy'" : "dF/dy ") << " " << n << " x " << n << ": max |analytic - fd| = " << worst
                << ", max |fd| = " << largest << "\n";
      EXPECT_GT(largest, 0);
      EXPECT_LT(worst, 1e-7 * largest);
    }
  std::vector<double> J0(std::size_t(n) * n), J1(std::size_t(n) * n);
  s.assemble_jacobian(t, 0.0, y, yp);
  for (unsigned int r = 0; r < n; ++r)
    for (unsigned int c = 0; c < n; ++c) J0[std::size_t(c) * n + r] = matrix_entry(s.jacobian(), r, c);
  s.assemble_jacobian(t, 1.0, y, yp);
  // Per entry, relative to the entries subtracted (J reaches 4e8 where M is 5): rounding of
  // J(1) - J(0) is eps times them.
  double worst = 0;
  for (unsigned int r = 0; r < n; ++r)
    for (unsigned int c = 0; c < n; ++c)
      {
        const std::size_t k = std::size_t(c) * n + r;
        const double J1 = matrix_entry(s.jacobian(), r, c);
        const double scale = std::abs(J1) + std::abs(J0[k]) + std::abs(M[k]);
        if (scale > 0) worst = std::max(worst, std::abs(J1 - J0[k] - M[k]) / scale);
      }
  std::cout << "  max |J(1) - J(0) - dF/dy'| / (|J(1)| + |J(0)| + |dF/dy'|) = " << worst << "\n";
  EXPECT_LT(worst, 1e-12);
}
