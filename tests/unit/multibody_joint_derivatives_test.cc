// Issue 24, item 1: the analytic second derivatives of the generic joint
// (GenericJoint::derivatives: d(B^T lambda)/dq, d(B^T mu)/dq, d(B v + Phi_t)/dq) against central
// differences of B^T w and B v + Phi_t from Joint::evaluate, per joint kind, at random states:
// Euler parameters off the unit sphere, modal coordinates, velocities and multipliers far from
// any solution. Bodies: two flexible curved arms (interfaces with translation and rotation mode
// shapes), a rigid block and the ground; track joints on the arms (contacts at random arc
// lengths, whose second derivatives come from differences of the track marker alone). Then the assembled DAE Jacobian with the analytic
// joints against the one with every joint by differences (System::use_element_differences).
// The forces likewise: dQ/dq and dQ/dv of each force kind (Force::derivatives) against central
// differences of its generalised forces, and a spring between two points of one flexible body
// (whose element lists the body's columns twice) in a whole Jacobian against central differences
// of the whole residual.
// Reference: central differences, h = 1e-6 (1 + |q_c|): truncation h^2 (third derivatives) and
// rounding eps |B| / h, both about 1e-10 of the largest entry here.
// Tolerance (issue 24's acceptance): 1e-7 of the largest entry of each block.
#include "curved_arm_body.h"
#include "multibody_test_helpers.h"

#include <multibody/force.h>
#include <multibody/generic_joint.h>

#include <Epetra_CrsMatrix.h>

#include <gtest/gtest.h>

#include <iostream>
#include <random>

using namespace flextrack;
using namespace flextrack::multibody;
using dealii::FullMatrix;
using dealii::Vector;

namespace
{
struct JointCase
{
  std::string kind, body1, body2, interface1, interface2, driver;
  std::string sliding = "", arm = "", arm_1 = "", sliding_1 = "", driver_1 = "";
};

const std::vector<JointCase> cases = {
  {"revolute", "arm1", "ground", "root", "", "0.3*sin(2*t) + t"}, // driven angle
  {"fixed", "arm2", "arm1", "root", "tip", ""},
  {"prismatic", "block", "arm1", "", "tip", "0.1*t^2"},            // driven displacement
  {"spherical", "block", "arm2", "", "tip", ""},
  {"cylindrical", "arm2", "block", "tip", "", ""},
  {"universal", "arm1", "arm2", "tip", "root", ""},
  {"planar", "block", "ground", "", "", ""},
  {"point_in_plane", "arm2", "ground", "tip", "", ""},
  {"revolute", "block", "arm2", "", "tip", ""},
  {"revolute", "block", "arm2", "", "tip", "0.5*t + 0.1*sin(3*t)"}, // driven angle on two moving bodies
  {"spherical", "ground", "arm1", "", "tip", ""},                    // the ground as body 1
  // Track joints: a contact at arc length s on arm 'arc' of body 2 (own coordinate s).
  {"prismatic_on_track", "block", "arm1", "", "", "0.2 + 0.1*t", "motion", "arc"},
  {"point_on_track", "arm2", "arm1", "tip", "", "", "free", "arc"},
  {"cylindrical_on_track", "block", "arm2", "", "", "2*sin(t)", "force", "arc"},
  {"double_arm_sleeve", "arm2", "arm1", "", "", "", "free", "arc", "arc", "force", "3*t"},
};

void build(System &s)
{
  const auto arm = flextrack::test::curved_arm(false);
  // Both arms where they were reduced: the sleeve's two contacts then meet at equal arc lengths.
  s.add_body(std::make_unique<FloatingBody>("arm1", arm, FlexibleOptions(), InitialState()));
  s.add_body(std::make_unique<FloatingBody>("arm2", arm, FlexibleOptions(), InitialState()));
  Matrix3 inertia;
  inertia[0][0] = 0.02, inertia[1][1] = 0.03, inertia[2][2] = 0.04;
  multibody::test::add_rigid(s, "block", 1.5, inertia, Vector3({0.4, 0.1, -0.2}));
  for (unsigned int k = 0; k < cases.size(); ++k)
    {
      const JointCase &c = cases[k];
      dealii::ParameterHandler prm;
      declare_joint_parameters(prm);
      prm.set("Kind", c.kind);
      prm.set("Body 1", c.body1);
      prm.set("Body 2", c.body2);
      prm.set("Interface 1", c.interface1);
      prm.set("Interface 2", c.interface2);
      prm.set("Position", "0.3, 0.2, 0.1");
      prm.set("Axis", "0.2, 0.3, 1");
      prm.set("Driver", c.driver);
      if (!c.arm.empty())
        {
          prm.set("Arm", c.arm);
          prm.set("Sliding", c.sliding);
          prm.set("Friction", "3");
          if (c.sliding != "motion") prm.set("Start arc length", "0.3");
        }
      if (!c.arm_1.empty())
        {
          prm.set("Arm 1", c.arm_1);
          prm.set("Sliding 1", c.sliding_1);
          prm.set("Driver 1", c.driver_1);
          prm.set("Friction 1", "2");
          prm.set("Start arc length 1", "0.3");
        }
      s.add_joint(create_joint("j" + std::to_string(k), prm, s.body_lookup()));
    }
}

/// A random state of each body (R, p with |p| != 1, eta, v), then the joint's own coordinates
/// (a contact's s and s').
struct BodyState
{
  std::vector<double> q, v;
};

/// B^T w (per body, then own coordinates, concatenated) and B v + Phi_t at @p state.
void joint_terms(const Joint &joint, const std::vector<BodyState> &state, const double t, const std::vector<double> &w,
                 std::vector<double> &Btw, std::vector<double> &rate)
{
  const unsigned int n_bodies = joint.bodies().size();
  std::vector<const double *> q;
  for (unsigned int b = 0; b < n_bodies; ++b) q.push_back(state[b].q.empty() ? nullptr : state[b].q.data());
  const BodyState &own = state[n_bodies];
  JointEvaluation e;
  joint.evaluate(q, own.q.empty() ? nullptr : own.q.data(), t, e);
  Btw.clear();
  rate.assign(e.phi.size(), 0.0);
  for (unsigned int r = 0; r < e.phi.size(); ++r) rate[r] = e.phi_t[r];
  for (unsigned int b = 0; b <= n_bodies; ++b)
    {
      const FullMatrix<double> &B = b < n_bodies ? e.B[b] : e.B_own;
      for (unsigned int c = 0; c < B.n(); ++c)
        {
          double sum = 0;
          for (unsigned int r = 0; r < e.phi.size(); ++r)
            {
              sum += B(r, c) * w[r];
              rate[r] += B(r, c) * state[b].v[c];
            }
          Btw.push_back(sum);
        }
    }
}

/// Largest |analytic - central difference| over the largest entry, of each derivative; and
/// column by column, over the column's largest entry (at least 1e-3 of the block's, where the
/// differences' rounding, about 1e-10 of the block's values, would dominate a smaller one).
struct Deviation
{
  double lambda = 0, mu = 0, rate = 0, column = 0;
};

/// Random states of a joint's bodies (Euler parameters off the unit sphere), its own
/// coordinates (the last entry) and random multipliers.
struct RandomJointState
{
  std::vector<BodyState> state;
  std::vector<double> lambda, mu;
};

RandomJointState random_state(const Joint &joint, const unsigned int seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  RandomJointState r;
  for (const Body *b : joint.bodies())
    {
      BodyState s;
      s.q.resize(b->n_q()), s.v.resize(b->n_v());
      if (b->n_q())
        {
          for (unsigned int i = 0; i < 3; ++i) s.q[i] = 0.5 * u(rng);
          for (unsigned int i = 3; i < 7; ++i) s.q[i] = 0.6 * u(rng);
          for (unsigned int i = 7; i < b->n_q(); ++i) s.q[i] = 0.05 * u(rng);
          for (unsigned int i = 0; i < b->n_v(); ++i) s.v[i] = 2 * u(rng);
        }
      r.state.push_back(s);
    }
  BodyState own; // arc lengths within the arm (0.6 m long), sliding speeds
  for (unsigned int i = 0; i < joint.n_own_coordinates(); ++i)
    own.q.push_back(0.3 + 0.15 * u(rng)), own.v.push_back(u(rng));
  r.state.push_back(own);
  const unsigned int m = joint.n_equations();
  r.lambda.resize(m), r.mu.resize(m);
  for (unsigned int k = 0; k < m; ++k) r.lambda[k] = 10 * u(rng), r.mu[k] = 10 * u(rng);
  return r;
}

Deviation compare(const Joint &joint, const unsigned int seed, const double t)
{
  RandomJointState random = random_state(joint, seed);
  std::vector<BodyState> &state = random.state;
  const BodyState &own = state.back();
  const std::vector<double> &lambda = random.lambda, &mu = random.mu;

  std::vector<const double *> q, v;
  for (unsigned int b = 0; b + 1 < state.size(); ++b)
    q.push_back(state[b].q.empty() ? nullptr : state[b].q.data()), v.push_back(state[b].v.empty() ? nullptr : state[b].v.data());
  JointDerivatives d;
  EXPECT_TRUE(joint.derivatives(q, own.q.empty() ? nullptr : state.back().q.data(), t, lambda.data(), mu.data(), v,
                                own.v.empty() ? nullptr : state.back().v.data(), d))
    << joint.name();

  double worst[3] = {0, 0, 0}, largest[3] = {0, 0, 0};
  std::vector<std::array<double, 3>> column_worst, column_largest;
  unsigned int column = 0;
  for (BodyState &b : state)
    for (unsigned int c = 0; c < b.q.size(); ++c, ++column)
      {
        const double x0 = b.q[c], h = 1e-6 * (1 + std::abs(x0));
        std::vector<double> lp, lm, mp, mm, rp, rm;
        b.q[c] = x0 + h;
        joint_terms(joint, state, t, lambda, lp, rp);
        joint_terms(joint, state, t, mu, mp, rp);
        b.q[c] = x0 - h;
        joint_terms(joint, state, t, lambda, lm, rm);
        joint_terms(joint, state, t, mu, mm, rm);
        b.q[c] = x0;
        column_worst.push_back({{0, 0, 0}});
        column_largest.push_back({{0, 0, 0}});
        const auto check = [&](const unsigned int k, const std::vector<double> &p, const std::vector<double> &n,
                               const FullMatrix<double> &analytic) {
          for (unsigned int r = 0; r < p.size(); ++r)
            {
              const double fd = (p[r] - n[r]) / (2 * h), deviation = std::abs(fd - analytic(r, column));
              largest[k] = std::max(largest[k], std::abs(fd));
              worst[k] = std::max(worst[k], deviation);
              column_largest.back()[k] = std::max(column_largest.back()[k], std::abs(fd));
              column_worst.back()[k] = std::max(column_worst.back()[k], deviation);
            }
        };
        check(0, lp, lm, d.lambda_q);
        check(1, mp, mm, d.mu_q);
        check(2, rp, rm, d.rate_q);
      }
  double by_column = 0;
  for (unsigned int c = 0; c < column_worst.size(); ++c)
    for (unsigned int k = 0; k < 3; ++k)
      by_column = std::max(by_column, column_worst[c][k] / std::max(column_largest[c][k], 1e-3 * largest[k]));
  return {worst[0] / largest[0], worst[1] / largest[1], worst[2] / largest[2], by_column};
}

} // namespace

TEST(MultibodyJointDerivatives, generic_joints_match_central_differences_per_kind)
{
  System s(Vector3({0, 0, -9.81}));
  build(s);
  for (unsigned int j = 0; j < s.n_joints(); ++j)
    for (const unsigned int seed : {1u, 2u, 3u})
      {
        const Deviation d = compare(s.joint(j), 10 * j + seed, 0.7);
        std::cout << "  " << cases[j].kind << " (" << cases[j].body1 << ", " << cases[j].body2 << "), state " << seed
                  << ": |D - D_fd| / max |D_fd|: d(B^T lambda)/dq " << d.lambda << ", d(B^T mu)/dq " << d.mu
                  << ", d(B v + Phi_t)/dq " << d.rate << "; column by column " << d.column << "\n";
        EXPECT_LT(d.column, 1e-6) << cases[j].kind;
        EXPECT_LT(d.lambda, 1e-7) << cases[j].kind;
        EXPECT_LT(d.mu, 1e-7) << cases[j].kind;
        EXPECT_LT(d.rate, 1e-7) << cases[j].kind;
      }
}

// Joint::residual_terms (what the DAE residual takes of a joint, computed from the markers'
// Jacobians without forming B) against the products with B itself (Joint::evaluate): equal to
// round-off, 1e-13 of the largest entry (sums of a few tens of terms of size 1-100). And
// Joint::driver_rates (the markers' axes alone) against evaluate()'s Phi_t, to 1e-14.
TEST(MultibodyJointDerivatives, residual_terms_equal_the_products_with_B_per_kind)
{
  System s(Vector3({0, 0, -9.81}));
  build(s);
  for (unsigned int j = 0; j < s.n_joints(); ++j)
    for (const unsigned int seed : {1u, 2u})
      {
        const Joint &joint = s.joint(j);
        const RandomJointState random = random_state(joint, 10 * j + seed);
        const auto &state = random.state;
        std::vector<double> B_lambda, B_mu, rate;
        joint_terms(joint, state, 0.7, random.lambda, B_lambda, rate);
        joint_terms(joint, state, 0.7, random.mu, B_mu, rate);
        std::vector<const double *> q, v;
        for (unsigned int b = 0; b + 1 < state.size(); ++b)
          q.push_back(state[b].q.empty() ? nullptr : state[b].q.data()),
            v.push_back(state[b].v.empty() ? nullptr : state[b].v.data());
        const bool own = !state.back().q.empty();
        JointResidualTerms terms;
        joint.residual_terms(q, own ? state.back().q.data() : nullptr, 0.7, v, own ? state.back().v.data() : nullptr,
                             random.lambda.data(), random.mu.data(), terms);
        JointEvaluation e;
        joint.evaluate(q, own ? state.back().q.data() : nullptr, 0.7, e);
        const auto relative = [](const std::vector<double> &a, const std::vector<double> &b) {
          double worst = 0, largest = 0;
          for (unsigned int i = 0; i < a.size(); ++i)
            worst = std::max(worst, std::abs(a[i] - b[i])), largest = std::max(largest, std::abs(b[i]));
          return worst / largest;
        };
        ASSERT_EQ(terms.force_lambda.size(), B_lambda.size()) << cases[j].kind;
        EXPECT_LT(relative(terms.force_lambda, B_lambda), 1e-13) << cases[j].kind << ": B^T lambda";
        EXPECT_LT(relative(terms.force_mu, B_mu), 1e-13) << cases[j].kind << ": B^T mu";
        EXPECT_LT(relative(std::vector<double>(terms.rate.begin(), terms.rate.end()), rate), 1e-13)
          << cases[j].kind << ": B v + Phi_t";
        EXPECT_EQ(std::vector<double>(terms.phi.begin(), terms.phi.end()), std::vector<double>(e.phi.begin(), e.phi.end()))
          << cases[j].kind << ": Phi";
        // driver_rates (the markers' axes alone, no Jacobians) against evaluate()'s Phi_t.
        Vector<double> rates;
        joint.driver_rates(q, own ? state.back().q.data() : nullptr, 0.7, rates);
        for (unsigned int r = 0; r < rates.size(); ++r)
          EXPECT_NEAR(rates[r], e.phi_t[r], 1e-14 * std::max(1.0, std::abs(e.phi_t[r]))) << cases[j].kind << ": Phi_t";
      }
}

TEST(MultibodyJointDerivatives, assembled_jacobian_equals_the_one_by_joint_differences)
{
  System s(Vector3({0, 0, -9.81}));
  build(s);
  s.finalize();
  s.drop_equations({{1, 0}, {3, 2}, {12, 1}}); // dropped (redundant) rows: lambda and mu by active index
  s.set_held(2, true);                         // the bead's contact held at its lower end stop
  Vector<double> y, yp;
  s.initial_guess(y);
  yp.reinit(y.size());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (unsigned int i = 0; i < y.size(); ++i) y[i] += 0.05 * u(rng), yp[i] = 0.5 * u(rng);
  for (unsigned int i = s.n_q() + s.n_v(); i < y.size(); ++i) y[i] = 10 * u(rng); // multipliers
  const double t = 0.7, alpha = 7; // alpha enters both the same way
  s.assemble_jacobian(t, alpha, y, yp);
  const unsigned int n = y.size();
  std::vector<double> analytic(n * n);
  for (unsigned int r = 0; r < n; ++r)
    for (unsigned int c = 0; c < n; ++c) analytic[r * n + c] = multibody::test::matrix_entry(s.jacobian(), r, c);
  s.use_element_differences(true);
  s.assemble_jacobian(t, alpha, y, yp);
  // Row by row: the largest difference in a row over the row's largest entry (the own
  // coordinates' rows hold entries of order 1 beside modal entries of order 1e5 elsewhere).
  double worst = 0;
  unsigned int worst_row = 0;
  for (unsigned int r = 0; r < n; ++r)
    {
      double difference = 0, largest = 0;
      for (unsigned int c = 0; c < n; ++c)
        {
          const double fd = multibody::test::matrix_entry(s.jacobian(), r, c);
          largest = std::max(largest, std::abs(fd));
          difference = std::max(difference, std::abs(fd - analytic[r * n + c]));
        }
      if (largest > 0 && difference / largest > worst) worst = difference / largest, worst_row = r;
    }
  std::cout << "  Jacobian " << n << " x " << n << ": max over rows of max |J - J_fd| / max |J_fd| = " << worst
            << " (row " << s.component_name(worst_row) << ")\n";
  EXPECT_LT(worst, 1e-7);
}

namespace
{
struct ForceCase
{
  std::string kind, body1, body2, interface1, interface2;
  bool marker_axes = false;
};

// Markers at interfaces move with the interface modes (translation and rotation shapes).
const std::vector<ForceCase> force_cases = {
  {"applied load", "arm1", "", "tip", "", false},
  {"applied load", "block", "", "", "", true},
  {"applied load", "arm2", "", "tip", "", true},
  {"spring damper", "arm1", "arm2", "tip", "root", false},
  {"spring damper", "block", "ground", "", "", false},
  {"rotational spring damper", "arm2", "block", "root", "", false},
  {"rotational spring damper", "arm1", "ground", "tip", "", false},
};

std::unique_ptr<Marker> force_marker(const System &s, const std::string &body, const std::string &interface,
                                     const Vector3 &position, const std::string &name)
{
  const Body &b = *s.find_body(body);
  std::vector<double> q(b.n_q()), v(b.n_v());
  b.initial_coordinates(q.data(), v.data());
  Matrix3 axes; // z along (0.2, 0.3, 1), orthonormal
  const Vector3 z = Vector3({0.2, 0.3, 1}) / Vector3({0.2, 0.3, 1}).norm();
  const Vector3 x = cross_product_3d(Vector3({0, 1, 0}), z) / cross_product_3d(Vector3({0, 1, 0}), z).norm();
  const Vector3 y = cross_product_3d(z, x);
  for (unsigned int i = 0; i < 3; ++i) axes[i][0] = x[i], axes[i][1] = y[i], axes[i][2] = z[i];
  return FixedMarker::at_global_pose(b, name, position, axes, q.data(), interface);
}

std::unique_ptr<Force> make_force(const System &s, const ForceCase &c, const unsigned int k)
{
  const std::string name = "f" + std::to_string(k);
  auto m1 = force_marker(s, c.body1, c.interface1, Vector3({0.3, 0.2, 0.1}), name + "_1");
  if (c.kind == "applied load")
    return std::make_unique<AppliedLoad>(
      name, std::move(m1),
      std::array<geometry::Expression, 3>{{geometry::Expression("3*sin(t)", "t"), geometry::Expression("2", "t"), geometry::Expression("-1 + t", "t")}},
      std::array<geometry::Expression, 3>{{geometry::Expression("0.5", "t"), geometry::Expression("cos(t)", "t"), geometry::Expression("0.2*t", "t")}},
      c.marker_axes);
  auto m2 = force_marker(s, c.body2, c.interface2, Vector3({-0.2, 0.4, 0.3}), name + "_2");
  if (c.kind == "spring damper") return std::make_unique<SpringDamper>(name, std::move(m1), std::move(m2), 150, 7, 0.3);
  return std::make_unique<RotationalSpringDamper>(name, std::move(m1), std::move(m2), 150, 7, 0.3);
}
} // namespace

TEST(MultibodyForceDerivatives, forces_match_central_differences_per_kind)
{
  // Reference: central differences of Q (Force::add_forces), h = 1e-6 (1 + |x|) in q and v.
  System s(Vector3({0, 0, -9.81}));
  build(s);
  for (unsigned int k = 0; k < force_cases.size(); ++k)
    {
      const auto force = make_force(s, force_cases[k], k);
      for (const unsigned int seed : {1u, 2u, 3u})
        {
          std::mt19937 rng(100 * k + seed);
          std::uniform_real_distribution<double> u(-1, 1);
          std::vector<std::vector<double>> q, v;
          unsigned int nv = 0;
          for (const Body *b : force->bodies())
            {
              q.emplace_back(b->n_q()), v.emplace_back(b->n_v());
              nv += b->n_v();
              for (unsigned int i = 0; i < b->n_q(); ++i) q.back()[i] = i < 3 ? 0.5 * u(rng) : i < 7 ? 0.6 * u(rng) : 0.05 * u(rng);
              for (unsigned int i = 0; i < b->n_v(); ++i) v.back()[i] = 2 * u(rng);
            }
          const double t = 0.7;
          const auto pointers = [](std::vector<std::vector<double>> &x) {
            std::vector<const double *> p;
            for (auto &b : x) p.push_back(b.empty() ? nullptr : b.data());
            return p;
          };
          const auto generalised = [&]() {
            std::vector<double> Q(nv, 0.0);
            std::vector<double *> Qb;
            unsigned int o = 0;
            for (const auto &b : v) Qb.push_back(Q.data() + o), o += b.size();
            force->add_forces(pointers(q), pointers(v), t, Qb);
            return Q;
          };
          FullMatrix<double> dq, dv;
          ASSERT_TRUE(force->derivatives(pointers(q), pointers(v), t, dq, dv)) << force_cases[k].kind;
          for (const bool in_q : {true, false})
            {
              std::vector<std::vector<double>> &x = in_q ? q : v;
              const FullMatrix<double> &analytic = in_q ? dq : dv;
              double worst = 0, largest = 0;
              unsigned int column = 0;
              for (auto &b : x)
                for (unsigned int c = 0; c < b.size(); ++c, ++column)
                  {
                    const double x0 = b[c], h = 1e-6 * (1 + std::abs(x0));
                    b[c] = x0 + h;
                    const auto Qp = generalised();
                    b[c] = x0 - h;
                    const auto Qm = generalised();
                    b[c] = x0;
                    for (unsigned int r = 0; r < nv; ++r)
                      {
                        const double fd = (Qp[r] - Qm[r]) / (2 * h);
                        largest = std::max(largest, std::abs(fd));
                        worst = std::max(worst, std::abs(fd - analytic(r, column)));
                      }
                  }
              if (largest == 0) // an applied load does not depend on v
                {
                  EXPECT_EQ(worst, 0) << force_cases[k].kind;
                  continue;
                }
              std::cout << "  " << force_cases[k].kind << " (" << force_cases[k].body1 << ", " << force_cases[k].body2
                        << (force_cases[k].marker_axes ? ", marker axes" : "") << "), state "
                        << seed << ": |dQ/d" << (in_q ? "q" : "v") << " - fd| / max |fd| = " << worst / largest << "\n";
              EXPECT_LT(worst, 1e-7 * largest) << force_cases[k].kind;
            }
        }
    }
}

TEST(MultibodyForceDerivatives, spring_on_one_flexible_body_matches_differences_of_the_residual)
{
  // A spring-damper between the root and the tip of one free flexible arm: its element lists the
  // arm's columns twice. Reference: central differences of the whole residual, h = 1e-5 (1 + |y|)
  // in q and v (the elastic forces K eta make the rounding eps |K eta| / h about 4e-6 of a row at
  // h = 1e-7; at 1e-5 the deviation measured 4.7e-8). Tolerance 1e-6 of each row's largest entry.
  // With the repeated columns differenced twice (the error this guards against) it is 2.6e-2.
  System s(Vector3({0, 0, -9.81}));
  s.add_body(std::make_unique<FloatingBody>("arm", flextrack::test::curved_arm(false), FlexibleOptions(), InitialState()));
  s.add_force(std::make_unique<SpringDamper>("inner", force_marker(s, "arm", "tip", Vector3(), "inner_1"),
                                             force_marker(s, "arm", "root", Vector3(), "inner_2"), 2e4, 50, 0.2));
  s.finalize();
  Vector<double> y, yp;
  s.initial_guess(y);
  yp.reinit(y.size());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (unsigned int i = 0; i < s.n_q() + s.n_v(); ++i) y[i] += (i >= 7 && i < s.n_q() ? 1e-3 : 0.05) * u(rng);
  for (unsigned int i = 0; i < y.size(); ++i) yp[i] = 0.5 * u(rng);
  const double t = 0.2, alpha = 0;
  s.assemble_jacobian(t, alpha, y, yp);
  double worst = 0;
  unsigned int worst_row = 0;
  std::vector<double> analytic(y.size() * y.size()), fd(y.size() * y.size());
  const unsigned int n = y.size();
  for (unsigned int r = 0; r < n; ++r)
    for (unsigned int c = 0; c < n; ++c) analytic[r * n + c] = multibody::test::matrix_entry(s.jacobian(), r, c);
  Vector<double> Fp, Fm;
  for (unsigned int c = 0; c < s.n_q() + s.n_v(); ++c)
    {
      const double h = 1e-5 * (1 + std::abs(y[c]));
      Vector<double> y1(y), y2(y);
      y1[c] += h, y2[c] -= h;
      s.residual(t, y1, yp, Fp);
      s.residual(t, y2, yp, Fm);
      for (unsigned int r = 0; r < n; ++r) fd[r * n + c] = (Fp[r] - Fm[r]) / (2 * h);
    }
  for (unsigned int r = s.n_q(); r < s.n_q() + s.n_v(); ++r) // the rows of the equations of motion
    {
      double difference = 0, largest = 0;
      for (unsigned int c = 0; c < s.n_q() + s.n_v(); ++c)
        {
          largest = std::max(largest, std::abs(fd[r * n + c]));
          difference = std::max(difference, std::abs(fd[r * n + c] - analytic[r * n + c]));
        }
      if (difference / largest > worst) worst = difference / largest, worst_row = r;
    }
  std::cout << "  max over rows of max |J - J_fd| / max |J_fd| = " << worst << " (row " << s.component_name(worst_row) << ")\n";
  EXPECT_LT(worst, 1e-6);
}
