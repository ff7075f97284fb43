// Redundant joint equations decided on a neighbourhood of the start (issue 23, item 2;
// multibody/redundancy.h): a start at a singular configuration (a slider-crank whose guide is
// turned so that crank and rod reach it in line, a four-bar with its links in line) is refused
// with the joints of the loop named; genuinely redundant loops (a planar four-bar or a
// slider-crank of revolute joints in 3D) still drop their dependent equations and run with every
// equation held; a dropped equation that stops holding ends the run with a report.
#include "multibody_test_helpers.h"

#include <base/input_error.h>
#include <multibody/end_stops.h>
#include <multibody/linearization.h>
#include <multibody/monitors.h>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

using namespace flextrack;
using namespace flextrack::multibody;
using namespace flextrack::multibody::test;
using dealii::Vector;

namespace
{
/// The slider-crank of prm/slider_crank.prm (crank r = 0.1 m driven at 2 pi rad/s, rod l =
/// 0.3 m, crank and rod in line along x at the start), its prismatic guide along @p guide_axis.
void slider_crank(System &s, const Vector3 &guide_axis)
{
  const double r = 0.1, l = 0.3;
  add_rigid(s, "crank", 0.5, diagonal(1e-4, 5e-4, 5e-4), Vector3({r / 2, 0, 0}));
  add_rigid(s, "rod", 1.0, diagonal(1e-4, 8e-3, 8e-3), Vector3({r + l / 2, 0, 0}));
  add_rigid(s, "slider", 2.0, diagonal(1e-3, 1e-3, 1e-3), Vector3({r + l, 0, 0}));
  add_joint(s, "revolute", "drive", "crank", "ground", Vector3(), Vector3({0, 0, 1}), "2*pi*t");
  add_joint(s, "revolute", "crank_pin", "rod", "crank", Vector3({r, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "revolute", "wrist_pin", "slider", "rod", Vector3({r + l, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "prismatic", "guide", "slider", "ground", Vector3({r + l, 0, 0}), guide_axis);
  s.finalize();
}

/// A four-bar of revolute joints about z with its links in line along x: ground pins A = (0,0,0)
/// and D, crank AB, coupler BC, rocker CD; bodies at the middle of their links.
void four_bar_in_line(System &s, const double B, const double C, const double D)
{
  add_rigid(s, "crank", 1.0, diagonal(0.01, 0.1, 0.1), Vector3({B / 2, 0, 0}));
  add_rigid(s, "coupler", 2.0, diagonal(0.01, 1.0, 1.0), Vector3({(B + C) / 2, 0, 0}));
  add_rigid(s, "rocker", 1.5, diagonal(0.01, 0.5, 0.5), Vector3({(C + D) / 2, 0, 0}));
  add_joint(s, "revolute", "A", "crank", "ground", Vector3(), Vector3({0, 0, 1}));
  add_joint(s, "revolute", "B", "coupler", "crank", Vector3({B, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "revolute", "C", "rocker", "coupler", Vector3({C, 0, 0}), Vector3({0, 0, 1}));
  add_joint(s, "revolute", "D", "rocker", "ground", Vector3({D, 0, 0}), Vector3({0, 0, 1}));
  s.finalize();
}

/// The message of the InputError that consistent_initial_conditions throws on @p s ("" if none).
std::string refusal(System &s)
{
  Vector<double> y, yp;
  try
    {
      consistent_initial_conditions(s, 0, y, yp);
    }
  catch (const InputError &e)
    {
      EXPECT_EQ(e.entry(), "Multibody/Joints");
      std::cout << "  refused: " << e.what() << "\n";
      return e.what();
    }
  return "";
}

bool names(const std::string &message, const std::string &joint)
{
  return message.find("'" + joint + "'") != std::string::npos;
}
} // namespace

TEST(MultibodyRedundancy, dead_point_slider_crank_is_refused_naming_its_loop)
{
  // The guide turned to y: the slider can stay on it only where crank and rod reach x = 0.4 m,
  // i.e. in line (the start). There the guide's translation along x depends on the other
  // equations to first order only; dropped, it let the slider leave the guide (issue 23).
  System s(Vector3({0, -9.81, 0}));
  slider_crank(s, Vector3({0, 1, 0}));
  const std::string message = refusal(s);
  ASSERT_NE(message.find("singular configuration"), std::string::npos);
  for (const std::string joint : {"drive", "crank_pin", "wrist_pin", "guide"}) EXPECT_TRUE(names(message, joint)) << joint;
  EXPECT_NE(message.find("dead point"), std::string::npos);
}

TEST(MultibodyRedundancy, slider_crank_in_line_along_its_guide_is_regular_and_keeps_three_redundant_equations)
{
  // prm/slider_crank.prm: crank and rod in line along the guide is a regular start (the slider
  // follows the crank there with zero speed); the planar loop makes 3 of 21 equations redundant.
  System s(Vector3({0, -9.81, 0}));
  slider_crank(s, Vector3({1, 0, 0}));
  Vector<double> y, yp;
  const auto report = consistent_initial_conditions(s, 0, y, yp);
  EXPECT_EQ(report.dropped.size(), 3u);
  for (const auto &d : report.dropped) EXPECT_EQ(d.joint, "guide");
  EXPECT_LT(report.position_residual, 1e-11);
}

TEST(MultibodyRedundancy, stretched_four_bar_is_refused_naming_its_joints)
{
  // Crank 1 m, coupler 2 m, rocker 1 m between pins 4 m apart: the links in line, stretched.
  // It cannot move at all (no assembled configuration nearby: a first-order motion of the links
  // is not a motion); dropping the equations of D let the rocker leave its pin by 2 m (issue 23).
  System s(Vector3({0, -9.81, 0}));
  four_bar_in_line(s, 1, 3, 4);
  const std::string message = refusal(s);
  ASSERT_NE(message.find("singular configuration"), std::string::npos);
  for (const std::string joint : {"A", "B", "C", "D"}) EXPECT_TRUE(names(message, joint)) << joint;
}

TEST(MultibodyRedundancy, parallelogram_with_links_in_line_is_refused)
{
  // A parallelogram four-bar (crank and rocker 1 m, coupler and ground 2 m) with its links in
  // line (A = 0, B = 1, C = 3, D = 2): a change point where the parallelogram and the
  // anti-parallelogram branches cross. It can move, but the rank of the joint equations there is
  // one less than on either branch.
  System s(Vector3({0, -9.81, 0}));
  four_bar_in_line(s, 1, 3, 2);
  const std::string message = refusal(s);
  ASSERT_NE(message.find("singular configuration"), std::string::npos);
  EXPECT_TRUE(names(message, "D"));
}

TEST(MultibodyRedundancy, planar_four_bar_drops_three_equations_and_holds_all_twenty)
{
  // The four-bar of MultibodyRigid.four_bar_linkage_runs_and_names_dropped_equations (crank AB =
  // 1 m up, coupler 2.5 m, rocker 2 m, pins 2 m apart, crank started at 1 rad/s): its planar loop
  // makes 3 of 20 equations redundant everywhere; they are confirmed at 4 configurations nearby,
  // dropped, and hold over the run (run through integrate_with_limits, which watches them).
  System s(Vector3({0, -9.81, 0}));
  add_planar_four_bar(s);
  Vector<double> y, yp;
  const auto report = consistent_initial_conditions(s, 0, y, yp);
  std::cout << report.text();
  ASSERT_EQ(report.dropped.size(), 3u);
  for (const auto &dropped : report.dropped) EXPECT_EQ(dropped.joint, "D");
  EXPECT_EQ(report.neighbours_checked, 4u);

  IdaIntegrator ida(s, tight(1e-8, 1e-10));
  ida.initialize(0, y, yp);
  Monitors monitors(s);
  double worst = 0, worst_active = 0, least_margin = 1;
  const std::string stop = integrate_with_limits(s, ida, 2.0, 0.05, [&](double t, const Vector<double> &yy, const Vector<double> &) {
    worst = std::max(worst, monitors.evaluate(t, yy).position_residual); // all 20 equations
    Vector<double> phi, phi_t;
    dealii::FullMatrix<double> Bm;
    s.constraints(t, yy, false, phi, Bm, phi_t);
    worst_active = std::max(worst_active, phi.linfty_norm());
    least_margin = std::min(least_margin, s.dropped_equation_margin(t, yy));
  });
  std::cout << "  four-bar: max |Phi| over 2 s: " << worst << " (all 20 equations), " << worst_active
            << " (the 17 active ones); least margin of the dropped ones " << least_margin << "\n";
  EXPECT_EQ(stop, "");
  EXPECT_NEAR(ida.time(), 2.0, 1e-12);
  EXPECT_LT(worst, 1e-7); // ~ tolerance x size, as in MultibodyRigid.four_bar_linkage_runs_and_names_dropped_equations
  EXPECT_GT(least_margin, 0.9 * System::dropped_equation_tolerance);
}

TEST(MultibodyRedundancy, linearize_of_a_stretched_four_bar_is_refused_before_any_mode)
{
  // flextrack linearize makes the start consistent first: the same refusal, so no "5.56 Hz mode"
  // of a mechanism that cannot move (issue 23).
  System s(Vector3({0, -9.81, 0}));
  four_bar_in_line(s, 1, 3, 4);
  Vector<double> y, yp;
  EXPECT_THROW(consistent_initial_conditions(s, 0, y, yp), InputError);
}

TEST(MultibodyRedundancy, run_stops_where_a_dropped_equation_stops_holding)
{
  // A pendulum (0.8 m, released from 0.5 rad) whose pivot's translation along x is dropped by
  // hand although it is not redundant: the pivot then slides along x as the bob swings (a
  // pendulum on a free rail), the dropped equation stops holding, and the run must end there
  // with a report naming the joint and the equation, not go on.
  const double L = 0.8, th = 0.5;
  System s(Vector3({0, -9.81, 0}));
  add_rigid(s, "bob", 1.0, diagonal(0.01, 0.01, 0.01), Vector3({L * std::sin(th), -L * std::cos(th), 0}),
            geometry::euler_parameters_from_axis_angle(Vector3({0, 0, 1}), th));
  add_joint(s, "revolute", "pivot", "bob", "ground", Vector3(), Vector3({0, 0, 1}));
  s.finalize();
  Vector<double> y, yp;
  const auto report = consistent_initial_conditions(s, 0, y, yp);
  ASSERT_TRUE(report.dropped.empty());
  unsigned int k = 0;
  while (s.joint(0).equation_name(k) != "translation along x") ++k;
  s.drop_equations({{0, k}});
  y.grow_or_shrink(s.size());
  consistent_derivatives(s, 0, y, yp);
  EXPECT_GT(s.dropped_equation_margin(0, y), 0);

  IdaIntegrator ida(s, tight(1e-8, 1e-10));
  ida.initialize(0, y, yp);
  const std::string stop = integrate_with_limits(s, ida, 2.0, 0.01, [](double, const Vector<double> &, const Vector<double> &) {});
  std::cout << "  " << stop << "\n";
  EXPECT_LT(ida.time(), 0.5);
  EXPECT_NE(stop.find("'translation along x' of joint 'pivot'"), std::string::npos);
  EXPECT_NE(stop.find("no longer holds"), std::string::npos);
}
