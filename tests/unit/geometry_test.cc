// Curve geometry against closed forms of differential geometry.
#include <fem/cross_section.h>
#include <geometry/curve_library.h>
#include <geometry/expression.h>
#include <geometry/section_frame.h>
#include <geometry/spline.h>
#include <base/input_error.h>

#include <gtest/gtest.h>

#include <random>

#include <chrono>
#include <cmath>

using namespace flextrack::geometry;

namespace
{
std::shared_ptr<const Curve> curve_from(const std::string &text)
{
  dealii::ParameterHandler prm;
  declare_curve_parameters(prm);
  prm.parse_input_from_string(text);
  return parse_curve(prm, {"Curve", "."});
}

// |value - reference| <= tol * max(1, |reference|)
void expect_close(double value, double reference, double tol, const std::string &what)
{
  EXPECT_LE(std::abs(value - reference), tol * std::max(1.0, std::abs(reference)))
    << what << ": " << value << " vs " << reference;
}
} // namespace

TEST(Expression, jets_give_exact_derivatives_of_composite_functions)
{
  // f(t) = exp(t) sin(t): closed-form derivatives f^(k) = 2^(k/2) exp(t) sin(t + k pi/4).
  const Expression f("exp(t) * sin(t)", "t");
  const double t = 0.7;
  const Jet j = f.jet(t);
  for (int k = 0; k <= 4; ++k)
    expect_close(j.derivative(k), std::pow(2.0, k / 2.0) * std::exp(t) * std::sin(t + k * M_PI / 4), 1e-14,
                 "derivative " + std::to_string(k));
  // g(t) = sqrt(1 + t^2) / atan(t) + log(t)^2 - t^-1.5: compare with its Taylor series from
  // a separate route (pow with real exponent and division), at order 1 by central difference
  // of the exact value with h = 1e-5 (truncation error ~ 1e-10).
  const Expression g("sqrt(1 + t^2) / atan(t) + log(t)^2 - t^(-1.5) + tanh(t) * cosh(t) / sinh(t)", "t");
  const double h = 1e-5;
  expect_close(g.jet(t).derivative(1), (g.value(t + h) - g.value(t - h)) / (2 * h), 1e-8, "g'");
  // tanh(t) cosh(t) / sinh(t) = 1: all derivatives vanish.
  const Jet one = Expression("tanh(t) * cosh(t) / sinh(t)", "t").jet(t);
  for (int k = 1; k <= 4; ++k) expect_close(one.derivative(k), 0.0, 1e-13, "d^k(1)");
}

TEST(Expression, first_order_jets_equal_the_leading_coefficients_of_full_jets_bit_for_bit)
{
  // taylor.h: every operation computes coefficient k from coefficients 0..k in the same order
  // whatever the truncation, so Expression::dual (order 1, used for a curve's speed and a drive's
  // rate) must return exactly the value and first derivative of Expression::jet (order 4).
  // Reference: the order-4 evaluation itself; tolerance 0 (bit for bit). One expression per
  // operation and function of the grammar (expression.h), at points inside every branch.
  const std::vector<std::string> texts = {
    "2*t^3 - t/(1 + t^2) + t^(-1.5) + t^0.7", "sin(t)*cos(2*t) - tan(t/3)", "sinh(t) + cosh(t/2)*tanh(t)",
    "exp(-t)*log(1 + t) + sqrt(2 + t)", "atan(3*t - 1) + abs(t - 0.5)", "min(t, 1 - t) + max(t^2, 0.3)",
    "if(t > 0.5, t^2, -t) + (t < 0.2) + (t >= 0.9) + (t <= 0.1)*t", "step(t - 0.4)*smoothstep(2*t - 0.3)",
    "(1 + t)^(t + 1)", "-(t - pi)^2"};
  for (const std::string &text : texts)
    {
      const Expression e(text, "t");
      for (const double t : {0.05, 0.3, 0.45, 0.55, 0.8, 0.95})
        {
          const Jet full = e.jet(t);
          const Dual first = e.dual(t);
          EXPECT_EQ(first.c[0], full.c[0]) << text << " at t = " << t;
          EXPECT_EQ(first.c[1], full.c[1]) << text << " at t = " << t;
        }
    }
  // An exponent with the variable in it whose slope vanishes at the point (cos at 0): both orders
  // take exp(e log b), decided when parsed; a test of the exponent's jet coefficients took the
  // power rule at order 1 only (3 against 3.0000000000000004).
  const Expression power("3^cos(t)", "t");
  EXPECT_EQ(power.dual(0).c[0], power.jet(0).c[0]);
  EXPECT_EQ(power.dual(0).c[1], power.jet(0).c[1]);
}

TEST(Expression, switching_functions_and_comparisons_for_laws_of_time)
{
  // Issue 25, item 14: a ramp-and-hold drive without tanh tricks. Values against the definitions
  // in expression.h; derivatives of smoothstep against its closed form
  // s(x) = 10x^3 - 15x^4 + 6x^5, s' = 30x^2 (1 - x)^2, s'' = 60x (1 - x)(1 - 2x), at x = 0.3.
  const Expression ramp_and_hold("0.5 * min(t, 2)", "t");
  EXPECT_EQ(ramp_and_hold.value(1), 0.5);
  EXPECT_EQ(ramp_and_hold.value(3), 1.0);
  EXPECT_EQ(ramp_and_hold.jet(1).derivative(1), 0.5);
  EXPECT_EQ(ramp_and_hold.jet(3).derivative(1), 0.0);
  const Expression later("if(t >= 1, (t - 1)^2, 0) + max(0, -t) + step(t - 4) * 7 + (t < 0.5) + (t > 9) + (t <= 2)", "t");
  EXPECT_EQ(later.value(0.25), 0.0 + 0 + 0 + 1 + 0 + 1);
  EXPECT_EQ(later.value(3), 4.0 + 0 + 0 + 0 + 0 + 0);
  EXPECT_EQ(later.value(4), 9.0 + 7);
  EXPECT_EQ(later.value(-2), 0.0 + 2 + 0 + 1 + 0 + 1);
  EXPECT_EQ(later.jet(3).derivative(1), 4.0);
  const Expression smooth("smoothstep(t)", "t");
  const double x = 0.3;
  const Jet j = smooth.jet(x);
  expect_close(j.derivative(0), 10 * std::pow(x, 3) - 15 * std::pow(x, 4) + 6 * std::pow(x, 5), 1e-15, "s");
  expect_close(j.derivative(1), 30 * x * x * (1 - x) * (1 - x), 1e-14, "s'");
  expect_close(j.derivative(2), 60 * x * (1 - x) * (1 - 2 * x), 1e-13, "s''");
  EXPECT_EQ(smooth.value(-1), 0.0);
  EXPECT_EQ(smooth.value(1.5), 1.0);
  // Wrong numbers of arguments are parse errors that say how many the function takes.
  for (const char *text : {"min(t)", "if(t, 1)", "step(t, 2)", "t < "})
    EXPECT_THROW(Expression(text, "t"), ExpressionError) << text;
  try
    {
      Expression("max(t)", "t");
    }
  catch (const ExpressionError &e)
    {
      EXPECT_NE(std::string(e.what()).find("(it takes 2)"), std::string::npos) << e.what();
    }
}

TEST(Expression, errors_name_position_and_expectation)
{
  try
    {
      Expression("sin(t) * (2 +", "t");
      FAIL() << "no error for an unfinished expression";
    }
  catch (const ExpressionError &e)
    {
      EXPECT_NE(std::string(e.what()).find("character"), std::string::npos) << e.what();
    }
  EXPECT_THROW(Expression("foo(t)", "t"), ExpressionError);
  EXPECT_THROW(Expression("a * t", "t"), ExpressionError); // a not declared
  EXPECT_NO_THROW(Expression("a * t", "t", parse_constants("a = 2, b = a^2")));
  EXPECT_EQ(parse_constants("a = 2, b = a^2").at("b"), 4.0);
}

namespace
{
std::string repeated(const std::string &piece, const int n)
{
  std::string s;
  for (int i = 0; i < n; ++i) s += piece;
  return s;
}

// The ExpressionError of @p text, or "" if it parses.
std::string expression_error(const std::string &text)
{
  try
    {
      Expression(text, "t");
    }
  catch (const ExpressionError &e)
    {
      return e.what();
    }
  return "";
}
} // namespace

TEST(Expression, nesting_up_to_the_limit_parses_and_beyond_is_refused_without_a_crash)
{
  // Issue 15, item 4: 100000 nested parentheses crashed the recursive parser (SIGSEGV).
  // At most max_expression_depth = 200 levels: parentheses, function arguments, signs, exponents.
  const int n = max_expression_depth;
  EXPECT_EQ(Expression(repeated("(", n) + "t" + repeated(")", n), "t").value(0.25), 0.25);
  EXPECT_EQ(Expression(repeated("-", n) + "t", "t").value(0.25), 0.25); // an even number of signs
  EXPECT_EQ(Expression(repeated("sin(", n - 1) + "t" + repeated(")", n - 1), "t").jet(0.0).derivative(1), 1.0);
  for (const std::string &deep : {repeated("(", n + 1) + "t" + repeated(")", n + 1), repeated("-", n + 1) + "t",
                                  repeated("t^", n + 1) + "t", repeated("abs(", n + 1) + "t" + repeated(")", n + 1)})
    {
      const std::string error = expression_error(deep);
      EXPECT_NE(error.find("nested deeper than 200 levels"), std::string::npos) << error;
      EXPECT_LT(error.size(), 400u) << "the message quotes an excerpt, not the whole text";
    }
  // The hostile inputs of the issue are refused by length (at most 10000 characters), quickly.
  for (const std::string &huge : {repeated("(", 100000) + "t" + repeated(")", 100000), repeated("-", 100000) + "t",
                                  repeated("t+", 199999) + "t", repeated("t^", 49999) + "t"})
    {
      const std::string error = expression_error(huge);
      EXPECT_NE(error.find("at most 10000 are allowed"), std::string::npos) << error.substr(0, 200);
      EXPECT_LT(error.size(), 400u);
    }
}

TEST(Expression, long_flat_sum_evaluates_without_recursion)
{
  // A sum of 4999 terms (9997 characters, within the limit) is a left-leaning tree 4999 nodes
  // deep; evaluation runs over the post-ordered node list, not recursively. Exact: every term
  // is t, and the sum of k equal binary doubles (k < 2^53 / t) is exact for t = 0.5.
  const Expression sum(repeated("t+", 4998) + "t", "t");
  EXPECT_EQ(sum.value(0.5), 4999 * 0.5);
  const Jet j = sum.jet(0.5);
  EXPECT_EQ(j.derivative(1), 4999.0);
  EXPECT_EQ(j.derivative(2), 0.0);
}

TEST(Expression, non_finite_numbers_and_constants_are_refused)
{
  EXPECT_NE(expression_error("1e400 * t").find("a finite number"), std::string::npos);
  EXPECT_THROW(parse_constants("a = 1e200, b = a * a"), ExpressionError); // b overflows to inf
  EXPECT_THROW(parse_constants("a = log(0)"), ExpressionError);           // -inf
  std::string many;
  for (std::size_t i = 0; i <= max_constants; ++i) many += "c" + std::to_string(i) + " = 1, ";
  EXPECT_THROW(parse_constants(many), ExpressionError);
}

TEST(Curve, pole_inside_the_parameter_range_is_refused_by_name)
{
  // Issue 15, item 6: y(t) = tan(t) over [0, 3] crosses its pole at pi/2, between the sample
  // points of the finiteness check; the arc length came out as 1.17e13 m and was accepted.
  try
    {
      curve_from("set Kind = parametric\nsubsection Parametric\n set x(t) = t\n set y(t) = tan(t)\n"
                 " set Parameter end = 3\nend\n");
      FAIL() << "a curve across a pole was accepted";
    }
  catch (const flextrack::InputError &e)
    {
      EXPECT_EQ(e.entry(), "Curve/Parametric");
      EXPECT_NE(e.message().find("allowed: at most 1e+06 m"), std::string::npos) << e.what();
    }
  // An absurd helix (1e9 turns) is refused on its entry.
  try
    {
      curve_from("set Kind = helix\nsubsection Helix\n set Turns = 1e9\nend\n");
      FAIL() << "1e9 turns accepted";
    }
  catch (const flextrack::InputError &e)
    {
      EXPECT_EQ(e.entry(), "Curve/Helix/Turns");
    }
}

TEST(Curve, spline_through_scattered_points_is_built_in_linear_time)
{
  // Issue 15, item 5: the arc-length table of a spline through scattered points demanded 1e-15
  // relative accuracy from panels whose Gauss nodes carry a rounding error of eps |p| (knots reach
  // p ~ 1e3): 2000 points took 80 s and 750 MiB. With the rounding floor in the tolerance:
  // ~8 table entries per segment. (A pseudo-random walk, deterministic.)
  std::vector<dealii::Point<3>> pts;
  unsigned long state = 12345;
  auto next = [&state] {
    state = state * 6364136223846793005ul + 1442695040888963407ul;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int i = 0; i < 2000; ++i) pts.emplace_back(next(), next(), next());
  const auto start = std::chrono::steady_clock::now();
  const auto curve = make_spline_curve(pts);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(std::isfinite(curve->length()));
  EXPECT_GT(curve->length(), 1000.0); // 1999 chords of mean length ~0.66
  EXPECT_LT(seconds, 10.0) << "took " << seconds << " s (0.1 s expected)";
  // The chord-length parametrisation is recovered: the arc length at the last knot is the
  // curve's length, and parameter_at inverts arc_length_at.
  const double s = 0.37 * curve->length();
  expect_close(curve->arc_length_at(curve->parameter_at(s)), s, 1e-9, "s(p(s))");
}

TEST(Curve, helix_from_expressions_matches_closed_forms)
{
  // Helix (a cos t, a sin t, c t): arc length t sqrt(a^2+c^2), curvature a/(a^2+c^2),
  // torsion c/(a^2+c^2), both constant (differential geometry; REFERENCES.md sec. 2).
  // Tolerance 1e-10 (issue 2 acceptance).
  const double a = 0.5, c = 0.15, w2 = a * a + c * c;
  const auto curve = curve_from("set Kind = parametric\nsubsection Parametric\n set Constants = a=0.5, c=0.15\n"
                                " set x(t) = a*cos(t)\n set y(t) = a*sin(t)\n set z(t) = c*t\n"
                                " set Parameter start = 0\n set Parameter end = 9.42477796076938\nend\n");
  expect_close(curve->length(), 9.42477796076938 * std::sqrt(w2), 1e-10, "length");
  for (const double t : {0.0, 0.3, 2.0, 5.5, 9.4})
    {
      expect_close(curve->arc_length_at(t), t * std::sqrt(w2), 1e-10, "s(t)");
      const double s = t * std::sqrt(w2);
      expect_close(curve->parameter_at(s), t, 1e-10, "t(s)");
      const CurveGeometry g = curve->geometry(s);
      expect_close(g.curvature, a / w2, 1e-10, "curvature");
      expect_close(g.torsion, c / w2, 1e-10, "torsion");
      expect_close(g.curvature_rate, 0.0, 1e-10, "curvature rate");
      expect_close(g.torsion_rate, 0.0, 1e-9, "torsion rate");
      expect_close(g.position[0], a * std::cos(t), 1e-10, "x");
      expect_close(g.tangent.norm(), 1.0, 1e-14, "|t|");
    }
}

TEST(Curve, arc_length_and_its_inverse_of_a_parabola_match_the_closed_form_inside_every_panel)
{
  // Parabola (t, t^2/2, 0), t in [0, 3]: s(t) = (t sqrt(1 + t^2) + asinh t) / 2 (calculus, any
  // table of integrals: int sqrt(1 + t^2) dt). Its speed is not constant, so the per-panel
  // Chebyshev series of the arc length (Curve::tabulate_series) is exercised away from its nodes:
  // 997 points, not aligned with the 64+ panels. Tolerance 2e-14 relative to the length (the
  // series are kept only where they reproduce the panels to 1e-14).
  const auto curve = curve_from("set Kind = parametric\nsubsection Parametric\n set x(t) = t\n set y(t) = t^2/2\n"
                                " set z(t) = 0\n set Parameter start = 0\n set Parameter end = 3\nend\n");
  const auto exact = [](const double t) { return 0.5 * (t * std::sqrt(1 + t * t) + std::asinh(t)); };
  const double L = exact(3.0);
  expect_close(curve->length(), L, 2e-14 * L, "length");
  double worst_s = 0, worst_t = 0;
  for (int k = 0; k <= 996; ++k)
    {
      const double t = 3.0 * k / 996.0 * (1 - 1e-9 * (k % 7));
      worst_s = std::max(worst_s, std::abs(curve->arc_length_at(t) - exact(t)));
      // t(s): the error in t is the error in s over the speed sqrt(1 + t^2) >= 1.
      worst_t = std::max(worst_t, std::abs(curve->parameter_at(exact(t)) - t));
    }
  EXPECT_LE(worst_s, 2e-14 * L);
  EXPECT_LE(worst_t, 2e-14 * L);
}

TEST(Curve, builtin_helix_is_exact)
{
  const auto curve = curve_from("set Kind = helix\nsubsection Helix\n set Radius = 0.5\n set Pitch = 0.4\n"
                                " set Turns = 2\nend\n");
  const double a = 0.5, c = 0.4 / (2 * M_PI), w2 = a * a + c * c;
  expect_close(curve->length(), 4 * M_PI * std::sqrt(w2), 1e-12, "length");
  const CurveGeometry g = curve->geometry(1.234);
  expect_close(g.curvature, a / w2, 1e-12, "curvature");
  expect_close(g.torsion, c / w2, 1e-12, "torsion");
}

TEST(Curve, ellipse_perimeter_matches_reference)
{
  // Perimeter of (2 cos t, sin t): 9.688448220547676 (complete elliptic integral of the second
  // kind, 4 a E(e), a = 2, e^2 = 3/4; REFERENCES.md sec. 2). Tolerance 1e-10 (issue 2).
  const auto curve = curve_from("set Kind = parametric\nsubsection Parametric\n set x(t) = 2*cos(t)\n"
                                " set y(t) = sin(t)\n set z(t) = 0\n set Parameter end = 6.283185307179586\nend\n");
  expect_close(curve->length(), 9.688448220547676, 1e-10, "perimeter");
  EXPECT_TRUE(curve->is_closed());
  // Curvature of the ellipse at t = 0 (vertex on the major axis): a / b^2 = 2.
  expect_close(curve->geometry(0.0).curvature, 2.0, 1e-10, "curvature at the vertex");
}

TEST(Curve, arc_length_curve_rejects_general_parameter)
{
  EXPECT_THROW(curve_from("set Kind = arc length\nsubsection Arc length\n set x(s) = 2*s\n set Length = 1\nend\n"),
               flextrack::InputError);
}

TEST(Curve, spline_through_circle_points_approximates_the_circle)
{
  // 129 points on a full circle of radius 1: length 2 pi and curvature 1,
  // up to the cubic spline's interpolation error (O(h^4) in position, h = 2 pi / 128).
  std::vector<dealii::Point<3>> pts;
  for (int i = 0; i <= 128; ++i)
    pts.emplace_back(std::cos(2 * M_PI * i / 128), std::sin(2 * M_PI * i / 128), 0.0);
  const auto curve = make_spline_curve(pts);
  EXPECT_NEAR(curve->length(), 2 * M_PI, 1e-5);
  EXPECT_NEAR(curve->geometry(M_PI).curvature, 1.0, 1e-3);
}

TEST(SectionFrame, frenet_frame_is_refused_on_a_straight_line)
{
  // Refused when the frame is built (before any FE work), naming where and what to use instead.
  const auto line = curve_from("set Kind = line\n");
  try
    {
      const SectionFrame frame(line, SectionFrame::Kind::frenet, Vec3({0, 0, 1}));
      FAIL() << "the Frenet frame of a straight line was accepted";
    }
  catch (const FrameError &e)
    {
      EXPECT_NE(std::string(e.what()).find("rotation minimising"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("s = 0 m"), std::string::npos) << e.what();
    }
  // A helix has no such point.
  EXPECT_NO_THROW(SectionFrame(curve_from("set Kind = helix\n"), SectionFrame::Kind::frenet, Vec3({0, 0, 1})));
}

TEST(SectionFrame, rotation_minimising_frame_turns_against_torsion_on_a_helix)
{
  // Along a curve, a rotation-minimising frame turns relative to the Frenet frame at the rate
  // -tau (Bishop, Amer. Math. Monthly 82, 1975): on a helix the angle is -tau s.
  const auto helix = curve_from("set Kind = helix\n");
  const SectionFrame rmf(helix, SectionFrame::Kind::rotation_minimising, helix->geometry(0).normal);
  for (const double s : {0.5, 2.0, 4.0})
    {
      const CurveGeometry g = helix->geometry(s);
      const Vec3 y = rmf.y_axis(s);
      const double angle = std::atan2(y * g.binormal, y * g.normal);
      EXPECT_NEAR(angle, -g.torsion * s, 1e-9) << "s = " << s;
      EXPECT_NEAR(y * g.tangent, 0.0, 1e-14);
    }
}

TEST(CrossSection, square_torsion_constant_matches_saint_venant)
{
  // Square a x a: J = 0.140577015 a^4 (Saint-Venant; REFERENCES.md sec. 1). Tolerance 1e-8.
  EXPECT_NEAR(flextrack::fem::CrossSection::rectangle_torsion_constant(0.1, 0.1) / 1e-4, 0.140577015, 1e-8);
}

TEST(SectionFrame, rate_is_the_derivative_of_the_frame_for_every_kind)
{
  // A contact sliding along an arm turns with d(d2)/ds = y_axis_rate; the velocity constraint
  // of a track joint uses it, the position constraint uses y_axis(s). Where the two disagree, the
  // velocity constraint is not the derivative of the position constraint. Reference: central
  // differences of y_axis(s), h = 1e-5 m (truncation h^2 |d2'''| / 6 ~ 1e-10, rounding
  // 1e-16 / h ~ 1e-11). Curve: the laser robot's arm I (prm/laser_robot_base.prm), a spatial arc
  // whose curvature and torsion vary. Tolerance 1e-8 1/m.
  const auto curve = curve_from("set Kind = parametric\nsubsection Parametric\n set x(t) = 0.15 + 0.9*(1 - cos(t))\n"
                                " set y(t) = 0.15 + 0.25*t\n set z(t) = 0.2 + 0.9*sin(t)\n"
                                " set Parameter end = 1.5707963267948966\nend\n");
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(0.01, curve->length() - 0.01);
  for (const auto kind : {SectionFrame::Kind::frenet, SectionFrame::Kind::rotation_minimising, SectionFrame::Kind::fixed_vector})
    {
      const SectionFrame frame(curve, kind, Vec3({1, 0, 0}));
      double worst = 0;
      for (int trial = 0; trial < 200; ++trial)
        {
          const double s = uniform(random), h = 1e-5;
          const CurveGeometry g = curve->geometry(s);
          const Vec3 rate = frame.y_axis_rate(g, frame.y_axis(g));
          const Vec3 difference = (frame.y_axis(s + h) - frame.y_axis(s - h)) / (2 * h);
          worst = std::max(worst, (rate - difference).norm());
        }
      std::cout << "  frame kind " << static_cast<int>(kind) << ": largest |y_axis_rate - d(y_axis)/ds| " << worst << " 1/m\n";
      EXPECT_LT(worst, 1e-8) << "frame kind " << static_cast<int>(kind);
    }
}
