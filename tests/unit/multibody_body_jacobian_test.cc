// Issue 24, item 1: the analytic derivatives of a body's equations of motion,
// F = M(q) v' - Q(q, v, v') (Body::equation_jacobians), against central differences of F itself,
// block by block (dF/dq, dF/dv, dF/dv'), at random states: Euler parameters off the unit sphere,
// modal coordinates, velocities and accelerations far from any solution, gravity on.
// Bodies: a rigid body with an off-centre mass and a full inertia tensor; a flexible curved arm
// (free-interface basis with two interfaces, a point mass, modal damping) with and without
// geometric stiffening; the same arm made rigid.
// Reference: central differences of F less its linear elastic part K eta (whose derivative K is
// exact by construction and would dwarf the inertia terms). In R and the Euler parameters with
// h = 1e-6 (1 + |x|): truncation h^2 x (third derivatives) and rounding eps |F| / h, both about
// 1e-10 of the block's largest entry here. F is a polynomial of degree 2 in eta and v and 1 in
// v', where central differences are exact for any step: there h = 1e-2 (1 + |x|), so that the
// rounding of the large elastic force in F (eps |K eta| / h) stays small.
// Tolerance (issue 24's acceptance): 1e-7 of the largest entry of each block.
#include "curved_arm_body.h"

#include <multibody/body.h>

#include <gtest/gtest.h>

#include <iostream>
#include <random>

using namespace flextrack;
using namespace flextrack::multibody;
using dealii::FullMatrix;

namespace
{
/// F = M(q) v' - Q(q, v, v') less the linear elastic force K eta: the stiffness entries are
/// orders of magnitude above the inertia terms, which would hide in a tolerance relative to them
/// (K itself is read from the reduced body file unchanged; its column is removed from the
/// analytic block too).
std::vector<double> equations(const FloatingBody &b, const std::vector<double> &q, const std::vector<double> &v,
                              const std::vector<double> &vp, const Vector3 &g)
{
  FullMatrix<double> M;
  b.mass_matrix(q.data(), M);
  std::vector<double> Q(b.n_v()), F(b.n_v());
  b.forces(q.data(), v.data(), g, Q.data(), vp.data());
  for (unsigned int i = 0; i < b.n_v(); ++i)
    {
      F[i] = -Q[i];
      for (unsigned int k = 0; k < b.n_v(); ++k) F[i] += M(i, k) * vp[k];
    }
  for (unsigned int j = 0; j < b.n_modes(); ++j)
    for (unsigned int k = 0; k < b.n_modes(); ++k) F[6 + j] -= b.reduced_body()->stiffness(j, k) * q[7 + k];
  return F;
}

/// Largest |analytic - central difference| of each block over its largest entry.
struct Deviation
{
  double q = 0, v = 0, vp = 0;
};

Deviation compare(const FloatingBody &b, const unsigned int seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> q(b.n_q()), v(b.n_v()), vp(b.n_v());
  b.initial_coordinates(q.data(), v.data());
  for (unsigned int i = 0; i < 3; ++i) q[i] = u(rng);
  for (unsigned int i = 3; i < 7; ++i) q[i] = 0.6 * u(rng); // |p| != 1: A is that of p / |p|
  for (unsigned int i = 7; i < b.n_q(); ++i) q[i] = 1e-3 * u(rng);
  for (unsigned int i = 0; i < b.n_v(); ++i) v[i] = 2 * u(rng), vp[i] = 20 * u(rng);
  const Vector3 g({0.3, -9.81, 1.2});

  FullMatrix<double> dq, dv, dvp;
  b.equation_jacobians(q.data(), v.data(), vp.data(), g, dq, dv, dvp);
  for (unsigned int j = 0; j < b.n_modes(); ++j)
    for (unsigned int k = 0; k < b.n_modes(); ++k) dq(6 + j, 7 + k) -= b.reduced_body()->stiffness(j, k);
  // step(c): the relative step of column c
  auto check = [&](std::vector<double> &x, const FullMatrix<double> &analytic, auto step) {
    double worst = 0, largest = 0;
    for (unsigned int c = 0; c < x.size(); ++c)
      {
        const double x0 = x[c], h = step(c) * (1 + std::abs(x0));
        x[c] = x0 + h;
        const auto Fp = equations(b, q, v, vp, g);
        x[c] = x0 - h;
        const auto Fm = equations(b, q, v, vp, g);
        x[c] = x0;
        for (unsigned int r = 0; r < b.n_v(); ++r)
          {
            const double fd = (Fp[r] - Fm[r]) / (2 * h);
            largest = std::max(largest, std::abs(fd));
            worst = std::max(worst, std::abs(fd - analytic(r, c)));
          }
      }
    return worst / largest;
  };
  Deviation d;
  d.q = check(q, dq, [](const unsigned int c) { return c < 7 ? 1e-6 : 1e-2; });
  d.v = check(v, dv, [](unsigned int) { return 1e-2; });
  d.vp = check(vp, dvp, [](unsigned int) { return 1e-2; });
  return d;
}

void expect_exact(const FloatingBody &b, const std::string &what)
{
  for (const unsigned int seed : {1u, 2u, 3u, 4u, 5u})
    {
      const Deviation d = compare(b, seed);
      std::cout << "  " << what << ", state " << seed << ": |J - J_fd| / max |J_fd|: dF/dq " << d.q << ", dF/dv "
                << d.v << ", dF/dv' " << d.vp << "\n";
      EXPECT_LT(d.q, 1e-7) << what;
      EXPECT_LT(d.v, 1e-7) << what;
      EXPECT_LT(d.vp, 1e-7) << what;
    }
}
} // namespace

TEST(MultibodyBodyJacobian, rigid_body_equations_match_central_differences)
{
  RigidProperties r;
  r.mass = 2.5;
  r.centre_of_mass = Vector3({0.1, -0.05, 0.2});
  r.inertia_centre_of_mass[0][0] = 0.3, r.inertia_centre_of_mass[1][1] = 0.2, r.inertia_centre_of_mass[2][2] = 0.25;
  r.inertia_centre_of_mass[0][1] = r.inertia_centre_of_mass[1][0] = 0.01;
  r.inertia_centre_of_mass[1][2] = r.inertia_centre_of_mass[2][1] = -0.02;
  r.inertia_centre_of_mass[0][2] = r.inertia_centre_of_mass[2][0] = 0.015;
  expect_exact(FloatingBody("rigid", r, InitialState()), "rigid body");
}

TEST(MultibodyBodyJacobian, flexible_body_equations_match_central_differences)
{
  const auto stiffened = test::curved_arm(true), plain = test::curved_arm(false);
  ASSERT_FALSE(stiffened->geometric_stiffness.empty());
  ASSERT_EQ(stiffened->damping.m(), stiffened->n_modes());
  FlexibleOptions off;
  off.geometric_stiffening = false;
  FlexibleOptions rigid;
  rigid.make_rigid = true;
  const FloatingBody with("arm", stiffened, FlexibleOptions(), InitialState());
  ASSERT_TRUE(with.geometric_stiffening());
  expect_exact(with, "flexible arm, geometric stiffening");
  expect_exact(FloatingBody("arm", plain, off, InitialState()), "flexible arm, no geometric stiffening");
  expect_exact(FloatingBody("arm", stiffened, rigid, InitialState()), "flexible arm made rigid");
}
