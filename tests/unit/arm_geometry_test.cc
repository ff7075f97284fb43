// The exact curve and section frame of a reduced body's arms travel in its file (issue 10, item
// 1): rebuilt from the stored parameter text they equal the scene's own geometry objects, a text
// that does not belong to the arm's nodes is refused naming the arm, and hostile texts are
// refused cleanly. Also the spline's "Inline points" entry that makes the text self-contained.
#include <base/input_error.h>
#include <fem/body_model.h>
#include <geometry/curve_library.h>
#include <geometry/spline.h>
#include <io/body_scene.h>
#include <io/reduced_body_file.h>
#include <reduction/arm_geometry.h>
#include <reduction/component_modes.h>
#include <reduction/reduced_body_builder.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <tuple>

#include <unistd.h>

using namespace flextrack;

namespace
{
// Three free-standing arms (no solid; each clamped at s = 0, said explicitly): an arc with the rotation-minimising
// frame, a helix with the Frenet frame, a spline (points from a file) with a fixed-vector frame.
const std::string three_arms_scene =
  "set Model = body\nsubsection Body\n set Solid = false\n set Arms = ring, coil, path\nend\n"
  "subsection Arm ring\n subsection Curve\n  set Kind = arc\n  subsection Arc\n   set Radius = 0.4\n"
  "   set Angle = 2.5\n   set Centre = -0.35, 0.1, 0.05\n  end\n end\n"
  " subsection Section frame\n  set Reference vector = 0.3, 0.2, 1\n end\n"
  " subsection Supports\n  set Start = clamped\n end\n subsection Mesh\n  set Number of elements = 8\n end\nend\n"
  "subsection Arm coil\n subsection Curve\n  set Kind = helix\n  subsection Helix\n   set Radius = 0.3\n"
  "   set Pitch = 0.2\n   set Turns = 1.25\n  end\n end\n subsection Section frame\n  set Kind = frenet\n end\n"
  " subsection Supports\n  set Start = clamped\n end\n subsection Mesh\n  set Number of elements = 10\n  set Element degree = 3\n end\nend\n"
  "subsection Arm path\n subsection Curve\n  set Kind = spline\n  subsection Spline\n   set Points file = points.txt\n"
  "  end\n end\n subsection Section frame\n  set Kind = fixed vector\n end\n"
  " subsection Supports\n  set Start = clamped\n end\n subsection Mesh\n  set Number of elements = 8\n end\nend\n"
  "subsection Reduction\n set Number of normal modes = 4\nend\n";

// Digits beyond what 6 significant digits would keep, so that the inline copy must be exact.
const std::string spline_points = "# x y z [m]\n0 0 0\n0.31415926535897931 0.1 0.05\n0.6 0.052718281828459045, 0.1\n"
                                  "0.9 -0.1 0.12345678901234567\n1.1 1e-3 0.2\n";

const std::string one_arc_scene =
  "set Model = body\nsubsection Body\n set Solid = false\n set Arms = ring\nend\n"
  "subsection Arm ring\n subsection Curve\n  set Kind = arc\n  subsection Arc\n   set Radius = 0.4\n"
  "   set Angle = 2.5\n  end\n end\n subsection Supports\n  set Start = clamped\n end\n subsection Mesh\n  set Number of elements = 6\n end\nend\n"
  "subsection Reduction\n set Number of normal modes = 3\nend\n";

struct TemporaryFolder
{
  std::filesystem::path path =
    std::filesystem::temp_directory_path() / ("flextrack_arm_geometry_" + std::to_string(::getpid()));
  TemporaryFolder() { std::filesystem::create_directories(path); }
  ~TemporaryFolder() { std::filesystem::remove_all(path); }
  std::string operator/(const std::string &name) const { return (path / name).string(); }
};

reduction::ReducedBody reduced(const io::BodyScene &scene)
{
  const fem::BodyModel model(scene.body);
  return reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), scene.reduction.method_name());
}

/// The message of the InputError that reading @p file throws ("" if none).
std::string refusal(const std::string &file)
{
  try
    {
      io::read_reduced_body(file);
    }
  catch (const InputError &e)
    {
      return e.what();
    }
  return "";
}
} // namespace

TEST(ArmGeometry, reduced_body_file_rebuilds_the_exact_curve_and_frame_of_arc_helix_and_spline_arms)
{
  // Reference: the scene's own Curve and SectionFrame objects (fem::Arm), built from the same
  // parameters. The file's text holds the same numbers (a spline's points at 17 digits), so the
  // rebuilt objects run the same code on the same doubles: equal to 1e-12 (relative to L for
  // positions; the y axis is a unit vector), measured 0. The points file is deleted before
  // reading: the file alone must be enough.
  const TemporaryFolder dir;
  std::ofstream(dir / "points.txt") << spline_points;
  const auto scene = io::read_body_scene_from_string(three_arms_scene, dir.path.string());
  const auto body = reduced(scene);
  io::write_reduced_body(body, dir / "body.h5");
  std::filesystem::remove(dir / "points.txt");
  const auto back = io::read_reduced_body(dir / "body.h5");
  ASSERT_EQ(back.arms.size(), 3u);
  for (unsigned int a = 0; a < 3; ++a)
    {
      const auto &original = scene.body.arms[a];
      const auto &arm = back.arms[a];
      EXPECT_EQ(arm.geometry_parameters, original.geometry_parameters);
      EXPECT_EQ(arm.geometry_parameters.find("points.txt"), std::string::npos); // no file name leaks in
      ASSERT_TRUE(arm.curve && arm.frame) << arm.name;
      EXPECT_EQ(arm.frame->kind(), original.frame->kind());
      const double L = original.curve->length();
      EXPECT_NEAR(arm.curve->length(), L, 1e-12 * L);
      double position_error = 0, frame_error = 0;
      for (unsigned int i = 0; i < 50; ++i)
        {
          const double s = L * i / 49;
          position_error = std::max(position_error, (arm.curve->position(s) - original.curve->position(s)).norm());
          frame_error = std::max(frame_error, (arm.frame->y_axis(s) - original.frame->y_axis(s)).norm());
        }
      std::cout << arm.name << " (" << arm.curve->description() << ", L = " << L << " m, text "
                << arm.geometry_parameters.size() << " bytes): position difference " << position_error
                << " m, y axis difference " << frame_error << "\n";
      EXPECT_LE(position_error, 1e-12 * L) << arm.name;
      EXPECT_LE(frame_error, 1e-12) << arm.name;
    }
  EXPECT_NE(back.arms[2].geometry_parameters.find("set Inline points = 0 0 0; 0.31415926535897931 0.10000000000000001"),
            std::string::npos)
    << back.arms[2].geometry_parameters;
  std::cout << "stored text of arm 'coil':\n" << back.arms[1].geometry_parameters;
}

TEST(ArmGeometry, file_whose_geometry_text_was_altered_is_refused_naming_the_arm)
{
  // A centre moved by 1 um moves every node by 1 um, 1000 times the tolerance (1e-9 L +
  // 1e-12 max |x|, about 1e-9 m here); a radius changed by 1 ppm or another angle changes the
  // length.
  const TemporaryFolder dir;
  auto body = reduced(io::read_body_scene_from_string(one_arc_scene));
  const std::string text = body.arms[0].geometry_parameters;
  const std::string file = dir / "body.h5";
  io::write_reduced_body(body, file);
  EXPECT_EQ(refusal(file), "");
  auto altered = [&](const std::string &from, const std::string &to) {
    auto changed = body;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    changed.arms[0].geometry_parameters.replace(at, from.size(), to);
    io::write_reduced_body(changed, file);
    return refusal(file);
  };
  const std::string centre = altered("set Centre = 0, 0, 0\n", "set Centre = 0, 1e-6, 0\n");
  std::cout << centre << "\n";
  EXPECT_NE(centre.find(file + ": not a valid reduced body: arm 'ring': the curve rebuilt from 'geometry_parameters' "
                               "(circular arc) is "),
            std::string::npos)
    << centre;
  EXPECT_NE(centre.find(" m away from the stored node position at s = "),
            std::string::npos)
    << centre;
  EXPECT_NE(centre.find("does not belong to this arm"), std::string::npos) << centre;
  const std::string radius = altered("set Radius = 0.4\n", "set Radius = 0.4000004\n");
  std::cout << radius << "\n";
  EXPECT_NE(radius.find("arm 'ring': the curve rebuilt from 'geometry_parameters' (circular arc) is L = 1.000001 m "
                        "long, the arm's cells end at 1 m"),
            std::string::npos)
    << radius;
  const std::string angle = altered("set Angle = 2.5\n", "set Angle = 2.6\n");
  EXPECT_NE(angle.find("arm 'ring': the curve rebuilt from 'geometry_parameters' (circular arc) is L = 1.04 m long"),
            std::string::npos)
    << angle;
  // Another section frame leaves the nodes where they are, and is accepted: the text is the
  // frame's only record (nothing stored to check it against).
  EXPECT_EQ(altered("set Kind = rotation minimising", "set Kind = frenet"), "");
}

TEST(ArmGeometry, hostile_geometry_texts_are_refused_cleanly)
{
  // Each text replaces the arm's; reading must throw InputError naming the file and the arm and
  // saying what is wrong, quickly, and never open another file.
  const TemporaryFolder dir;
  auto body = reduced(io::read_body_scene_from_string(one_arc_scene));
  const std::string file = dir / "body.h5";
  const std::string curve = "subsection Curve\n set Kind = spline\n subsection Spline\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
    {std::string(reduction::max_geometry_parameters_bytes + 1, 'x'),
     "is a string of 8388609 characters; at most 8388608 are allowed"},
    {"this is not a parameter file\n", "is not a curve and section frame"},
    {std::string(100000, '#') + "\nsubsection Solid\nend\n", "is not a curve and section frame"},
    {"include /etc/passwd\n", "includes another file ('include /etc/passwd')"},
    {"inc\\\nlude /etc/passwd\n", "holds the character code 92"},
    {curve + "  set Points file = /etc/passwd\n end\nend\n", "names a points file"},
    {curve + "  set Inline points = 0 0 0; 1 0 nan\n end\nend\n", "entry 'Curve/Spline/Inline points'"},
    {"subsection Curve\n set Kind = arc\n subsection Arc\n  set Radius = -1\n end\nend\n",
     "does not rebuild: entry 'Curve/Arc/Radius': must be > 0 m"},
    {"subsection Curve\n set Kind = parametric\n subsection Parametric\n  set x(t) = " + std::string(20000, '(') +
       "t\n end\nend\n",
     "does not rebuild: entry 'Curve/Parametric/x(t)'"},
    {std::string("subsection Curve\n") + char(1) + "\nend\n", "holds the character code 1"},
    {"", "is not a curve and section frame"}};
  for (const auto &[text, expected] : cases)
    {
      auto hostile = body;
      hostile.arms[0].geometry_parameters = text;
      io::write_reduced_body(hostile, file);
      const auto start = std::chrono::steady_clock::now();
      const std::string message = refusal(file);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cout << seconds << " s: " << message.substr(0, 240) << "\n";
      if (text.empty()) // nothing stored: a body that does not know its curve (below)
        {
          EXPECT_EQ(message, "");
          continue;
        }
      EXPECT_NE(message.find(file + ": not a valid reduced body: arm 'ring': "), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
      EXPECT_LT(message.size(), 1000u);
      EXPECT_LT(seconds, 5.0);
    }
}

TEST(ArmGeometry, an_arm_without_geometry_text_reads_without_curve_and_a_track_is_refused_naming_it)
{
  // An arm built in code has no parameter text: the file stores no geometry_parameters, the
  // reader leaves curve and frame null, and require_arm_geometry says so, naming the arm.
  const TemporaryFolder dir;
  auto body = reduced(io::read_body_scene_from_string(one_arc_scene));
  EXPECT_NO_THROW(reduction::require_arm_geometry(body.arms[0]));
  body.arms[0].geometry_parameters.clear();
  io::write_reduced_body(body, dir / "body.h5");
  const auto back = io::read_reduced_body(dir / "body.h5");
  EXPECT_FALSE(back.arms[0].curve);
  EXPECT_FALSE(back.arms[0].frame);
  try
    {
      reduction::require_arm_geometry(back.arms[0]);
      FAIL() << "no error for an arm without curve";
    }
  catch (const std::runtime_error &e)
    {
      EXPECT_NE(std::string(e.what()).find("arm 'ring' of the reduced body has no stored curve"), std::string::npos)
        << e.what();
    }
}

TEST(ArmGeometry, spline_points_inline_equal_the_points_file_and_are_range_checked)
{
  // The "Inline points" entry builds the same spline as the file (the same doubles: equal
  // bits); its values are checked like a points file's, naming the entry.
  const TemporaryFolder dir;
  std::ofstream(dir / "points.txt") << spline_points;
  auto spline = [&](const std::string &file, const std::string &points) {
    dealii::ParameterHandler prm;
    geometry::declare_curve_parameters(prm);
    prm.set("Kind", "spline");
    prm.enter_subsection("Spline");
    prm.set("Points file", file);
    prm.set("Inline points", points);
    prm.leave_subsection();
    return geometry::parse_curve(prm, {"Arm/Curve", dir.path.string()});
  };
  const auto from_file = spline("points.txt", "");
  const auto inline_points = spline("", "0 0 0; 0.31415926535897931, 0.1, 0.05; 0.6 0.052718281828459045 0.1;"
                                        " 0.9 -0.1 0.12345678901234567; 1.1 1e-3 0.2;");
  ASSERT_EQ(from_file->length(), inline_points->length());
  for (unsigned int i = 0; i <= 20; ++i)
    {
      const double s = from_file->length() * i / 20;
      EXPECT_EQ(from_file->position(s), inline_points->position(s));
    }
  const std::vector<std::pair<std::string, std::string>> refused = {
    {"0 0 0; 2e6 0 0", "entry 'Arm/Curve/Spline/Inline points': point 2: coordinate 2e+06 m; allowed: coordinates of at most"},
    {"0 0 0; 1 0 inf", "entry 'Arm/Curve/Spline/Inline points': 'inf' is not a finite number"},
    {"0 0 0; 1 0", "entry 'Arm/Curve/Spline/Inline points': point 2 is not three numbers"},
    {"0 0 0", "entry 'Arm/Curve/Spline/Inline points': 1 points; a spline needs at least 2"},
    {"0 0 0; 1 1 1; 1 1 1", "points 2 and 3 coincide"}};
  for (const auto &[points, expected] : refused)
    try
      {
        spline("", points);
        ADD_FAILURE() << "accepted " << points;
      }
    catch (const InputError &e)
      {
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      }
  for (const auto &[file, points, expected] :
       {std::tuple<std::string, std::string, std::string>{"points.txt", "0 0 0; 1 0 0",
                                                          "give either 'Points file' or 'Inline points', not both"},
        {"", "", "no points: give a 'Points file' or 'Inline points'"}})
    try
      {
        spline(file, points);
        ADD_FAILURE() << "accepted '" << file << "' and '" << points << "'";
      }
    catch (const InputError &e)
      {
        EXPECT_NE(std::string(e.what()).find("entry 'Arm/Curve/Spline/Points file': " + expected), std::string::npos)
          << e.what();
      }
}

TEST(ArmGeometry, an_arm_built_before_from_the_same_text_does_not_let_a_bad_spline_through)
{
  // fem::Arm takes a curve built earlier in the process from the same geometry text
  // (geometry/built_geometry.h). A spline with both a points file and inline points must still be
  // refused although, with the file's points inlined, its text would equal that of the file alone,
  // which was just built.
  const TemporaryFolder dir;
  std::ofstream(dir / "points.txt") << spline_points;
  const auto arm = [&](const std::string &points) {
    dealii::ParameterHandler prm;
    fem::Arm::declare_parameters(prm);
    prm.parse_input_from_string("subsection Arm\n subsection Curve\n  set Kind = spline\n  subsection Spline\n"
                                "   set Points file = points.txt\n   set Inline points = " + points +
                                "\n  end\n end\nend\n");
    return fem::Arm::parse_parameters(prm, dir.path.string());
  };
  const fem::Arm from_file = arm("");
  EXPECT_GT(from_file.curve->length(), 0);
  EXPECT_EQ(arm("").curve, from_file.curve); // the same text: the same curve object
  try
    {
      arm("0 0 0; 1 0 0");
      ADD_FAILURE() << "a points file and inline points were accepted together";
    }
  catch (const InputError &e)
    {
      EXPECT_NE(std::string(e.what()).find("give either 'Points file' or 'Inline points', not both"), std::string::npos)
        << e.what();
    }
}

TEST(ArmGeometry, text_of_expression_curves_with_constants_rebuilds_the_same_curve)
{
  // The text is written by walking the declared entries (fem::Arm::parse_parameters): a kind
  // whose subsection name has two words ("Arc length") and its Constants come along, the
  // other kinds' subsections do not. Reference: the arm's own curve, equal to 1e-12 L
  // (measured 0: same code, same numbers).
  for (const std::string kind : {"arc length", "parametric"})
    {
      dealii::ParameterHandler prm;
      fem::Arm::declare_parameters(prm);
      const std::string curve =
        kind == "arc length"
          ? " set Kind = arc length\n subsection Arc length\n  set Constants = a=0.5, c=0.1\n"
            "  set x(s) = a*cos(s/sqrt(a^2+c^2))\n  set y(s) = a*sin(s/sqrt(a^2+c^2))\n"
            "  set z(s) = c*s/sqrt(a^2+c^2)\n  set Length = 2.5\n end\n"
          : " set Kind = parametric\n subsection Parametric\n  set x(t) = 2*cos(t)\n  set y(t) = sin(t)\n"
            "  set z(t) = 0.1*t^2\n  set Parameter end = 3\n end\n";
      prm.parse_input_from_string("subsection Arm\n subsection Curve\n" + curve + " end\nend\n");
      const auto arm = fem::Arm::parse_parameters(prm, ".");
      EXPECT_NE(arm.geometry_parameters.find("set Kind = " + kind), std::string::npos) << arm.geometry_parameters;
      EXPECT_EQ(arm.geometry_parameters.find("subsection Helix"), std::string::npos) << arm.geometry_parameters;
      const auto rebuilt = reduction::parse_arm_geometry(arm.geometry_parameters);
      const double L = arm.curve->length();
      ASSERT_EQ(rebuilt.curve->length(), L);
      double error = 0;
      for (unsigned int i = 0; i < 50; ++i)
        error = std::max(error, (rebuilt.curve->position(L * i / 49) - arm.curve->position(L * i / 49)).norm());
      std::cout << kind << ": L = " << L << " m, position difference " << error << " m\n";
      EXPECT_LE(error, 1e-12 * L) << kind;
    }
}
