// The reduced body file (HDF5) and what it carries: bit-identical read-back, the input hash
// behind the cache, and the mode fields along arms (issue 4, items 4-6).
#include <fem/body_model.h>
#include <io/body_scene.h>
#include <io/reduced_body_file.h>
#include <reduction/component_modes.h>
#include <reduction/mode_field.h>
#include <reduction/reduced_body_builder.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

using namespace flextrack;

namespace
{
const std::string boom_scene =
  "set Model = body\nsubsection Body\n set Arms = boom\n set Ties = boom: rigid, within 0.03\n"
  " set Interfaces = tip: arm boom at 0.6283185307179586; side: point 0.1 0.05 0.05, within 0.03\n"
  " set Point masses = tip: 0.2\n set Output points = mid: arm boom at 0.3\nend\n"
  "subsection Solid\n set Mesh = box\n set Supports = YMIN: x, y, z\n subsection Box\n  set Size = 0.1, 0.1, 0.1\n"
  "  set Cells = 2, 2, 2\n end\nend\n"
  "subsection Arm boom\n subsection Curve\n  set Kind = arc\n  subsection Arc\n   set Radius = 0.4\n"
  "   set Centre = -0.35, 0.1, 0.05\n  end\n end\n subsection Supports\n  set Start = free\n end\n"
  " subsection Mesh\n  set Number of elements = 12\n  set Element degree = 3\n end\nend\n"
  "subsection Reduction\n set Number of normal modes = 6\n set Track arms = boom\n set Track stations = 4\n"
  " set Damping ratio = 0.02\n set Geometric stiffness = true\nend\n";

template <typename T>
bool same_bits(const T &a, const T &b)
{
  return a.size() == b.size() && (a.size() == 0 || std::memcmp(&a[0], &b[0], a.size() * sizeof(a[0])) == 0);
}

bool same_bits(const dealii::FullMatrix<double> &a, const dealii::FullMatrix<double> &b)
{
  if (a.m() != b.m() || a.n() != b.n()) return false;
  for (unsigned int i = 0; i < a.m(); ++i)
    for (unsigned int j = 0; j < a.n(); ++j)
      if (std::memcmp(&a(i, j), &b(i, j), sizeof(double)) != 0) return false;
  return true;
}

std::string bytes_of(const std::string &file)
{
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
} // namespace

TEST(ReducedBodyFile, reads_back_bit_identically)
{
  // Every number written is read back with the same bits (no text conversion anywhere), and
  // writing what was read gives the same file, byte for byte (no time stamps in the file).
  const auto scene = io::read_body_scene_from_string(boom_scene);
  const fem::BodyModel model(scene.body);
  auto body = reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), scene.reduction.method_name());
  body.input_hash = scene.input_hash;
  const auto dir = std::filesystem::temp_directory_path() / ("flextrack_h5_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string first = (dir / "a.h5").string(), second = (dir / "b.h5").string();
  io::write_reduced_body(body, first);
  const auto back = io::read_reduced_body(first);
  EXPECT_EQ(back.input_hash, body.input_hash);
  EXPECT_EQ(back.method, "craig bampton");
  EXPECT_TRUE(same_bits(back.stiffness, body.stiffness));
  EXPECT_TRUE(same_bits(back.mass, body.mass));
  EXPECT_TRUE(same_bits(back.damping, body.damping));
  EXPECT_TRUE(same_bits(back.frequencies_hz, body.frequencies_hz));
  ASSERT_EQ(back.geometric_stiffness.size(), 12u);
  for (unsigned int c = 0; c < 12; ++c) EXPECT_TRUE(same_bits(back.geometric_stiffness[c], body.geometric_stiffness[c]));
  EXPECT_EQ(std::memcmp(&back.invariants.mass, &body.invariants.mass, sizeof(double)), 0);
  EXPECT_TRUE(same_bits(back.invariants.I3, body.invariants.I3));
  EXPECT_TRUE(same_bits(back.invariants.I4, body.invariants.I4));
  EXPECT_TRUE(same_bits(back.invariants.P, body.invariants.P));
  EXPECT_TRUE(same_bits(back.invariants.Q, body.invariants.Q));
  ASSERT_EQ(back.interfaces.size(), 2u);
  EXPECT_EQ(back.interfaces[0].name, "tip");
  EXPECT_EQ(back.interfaces[1].name, "side");
  for (unsigned int i = 0; i < 2; ++i) EXPECT_TRUE(same_bits(back.interfaces[i].modes, body.interfaces[i].modes));
  ASSERT_EQ(back.output_points.size(), 1u);
  EXPECT_EQ(back.output_points[0].name, "mid");
  EXPECT_TRUE(same_bits(back.output_points[0].modes, body.output_points[0].modes));
  ASSERT_EQ(back.arms.size(), 1u);
  EXPECT_TRUE(same_bits(back.arms[0].values, body.arms[0].values));
  EXPECT_TRUE(same_bits(back.arms[0].cell_s, body.arms[0].cell_s));
  EXPECT_TRUE(same_bits(back.points, body.points));
  EXPECT_TRUE(same_bits(back.point_modes, body.point_modes));
  EXPECT_EQ(back.quads, body.quads);
  EXPECT_EQ(back.lines, body.lines);
  io::write_reduced_body(back, second);
  EXPECT_EQ(bytes_of(first), bytes_of(second));
  // Damping ratio 0.02 on a diagonal reduced model: C_kk = 2 zeta w_k (mass-normalised).
  EXPECT_NEAR(body.damping(0, 0), 2 * 0.02 * 2 * M_PI * body.frequencies_hz[0], 1e-9 * body.damping(0, 0));
  std::filesystem::remove_all(dir);
}

TEST(ReducedBodyFile, input_hash_follows_every_input)
{
  // The cache key must change with any parameter that affects the body and with the bytes of
  // a mesh file, and must not change with the output settings.
  const auto base = io::read_body_scene_from_string(boom_scene).input_hash;
  auto changed = [&](const std::string &from, const std::string &to) {
    std::string text = boom_scene;
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    return io::read_body_scene_from_string(text).input_hash;
  };
  EXPECT_NE(changed("set Radius = 0.4", "set Radius = 0.41"), base);
  EXPECT_NE(changed("within 0.03", "within 0.031"), base);
  EXPECT_NE(changed("tip: 0.2", "tip: 0.25"), base);
  EXPECT_NE(changed("set Track stations = 4", "set Track stations = 5"), base);
  EXPECT_NE(changed("set Number of normal modes = 6", "set Number of normal modes = 7"), base);
  EXPECT_EQ(changed("set Geometric stiffness = true\nend\n",
                    "set Geometric stiffness = true\nend\nsubsection Output\n set Directory = elsewhere\nend\n"),
            base);
  EXPECT_NE(changed("set Geometric stiffness = true", "set Geometric stiffness = false"), base);

  // A mesh file: change the last digit of one coordinate (a sub-micrometre move), the hash
  // changes; restore it, the hash returns.
  const auto dir = std::filesystem::temp_directory_path() / ("flextrack_hash_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string mesh = bytes_of(std::string(FLEXTRACK_TEST_DIR) + "/../meshes/curved_bracket.inp");
  const std::string scene = "set Model = body\nsubsection Solid\n set Mesh = file\n set Mesh file = bracket.inp\n"
                            " set Supports = FIX: x, y, z\nend\n";
  auto hash_with = [&](const std::string &bytes) {
    std::ofstream(dir / "bracket.inp", std::ios::binary) << bytes;
    return io::read_body_scene_from_string(scene, dir.string()).input_hash;
  };
  const auto h1 = hash_with(mesh);
  std::string edited = mesh;
  const std::string coordinate = "0.297433458412143"; // node 2 of the committed mesh
  const auto at = edited.find(coordinate);
  ASSERT_NE(at, std::string::npos);
  edited[at + coordinate.size() - 1] = '4';
  EXPECT_NE(hash_with(edited), h1);
  EXPECT_EQ(hash_with(mesh), h1);
  std::filesystem::remove_all(dir);
}

TEST(ArmModeField, finite_element_field_equals_the_beam_model_and_the_smoothed_field_is_C1)
{
  // (1) The FE interpolation of the stored nodal values equals the beam model's own
  //     displacement_at(s) at random s: same polynomials, 1e-12 relative.
  // (2) The smoothed field is C1: at every inner vertex the slopes from both sides agree to
  //     1e-6 (finite differences 1e-9 L apart), where the FE slopes jump (printed: track
  //     load modes have real shear kinks at their stations). Its values differ from the FE field
  //     by at most (4 b / 27) h |slope jump| / 2, b = 1/4 (mode_field.h): the smoothing is local.
  // (3) A point off the arm is refused, naming s and L.
  const auto scene = io::read_body_scene_from_string(boom_scene);
  const fem::BodyModel model(scene.body);
  const auto basis = reduction::reduce(model, scene.reduction);
  const auto body = reduction::make_reduced_body(model, basis, "craig bampton");
  const auto &data = body.arms[0];
  const reduction::ArmModeField fe(data, reduction::ArmModeField::Interpolation::finite_element);
  const reduction::ArmModeField smoothed(data); // the default: smoothed
  const unsigned int n = data.n_modes;
  std::vector<double> v(6 * n), d(6 * n), vh(6 * n), dh(6 * n);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(0, data.length());
  double largest = 0, fe_error = 0, smoothed_error = 0;
  for (int trial = 0; trial < 40; ++trial)
    {
      const double s = uniform(random);
      fe.evaluate(s, v.data(), d.data());
      smoothed.evaluate(s, vh.data(), dh.data());
      for (unsigned int k = 0; k < n; ++k)
        {
          const auto u = model.arm_displacement(0, s, basis.modes[k]);
          for (unsigned int c = 0; c < 3; ++c)
            {
              largest = std::max(largest, std::abs(u[c]));
              fe_error = std::max(fe_error, std::abs(v[6 * k + c] - u[c]));
              smoothed_error = std::max(smoothed_error, std::abs(vh[6 * k + c] - u[c]));
            }
        }
    }
  std::cout << "largest mode displacement " << largest << "; FE field error " << fe_error << "; smoothed - FE " << smoothed_error
            << "\n";
  EXPECT_LT(fe_error, 1e-12 * largest);
  double fe_jump = 0, smoothed_jump = 0, slope_scale = 0;
  for (unsigned int c = 1; c < data.n_cells(); ++c)
    {
      const double s = data.cell_s[c], eps = 1e-9 * data.length();
      std::vector<double> dl(6 * n), dr(6 * n), hl(6 * n), hr(6 * n);
      fe.evaluate(s - eps, v.data(), dl.data());
      fe.evaluate(s + eps, v.data(), dr.data());
      smoothed.evaluate(s - eps, v.data(), hl.data());
      smoothed.evaluate(s + eps, v.data(), hr.data());
      for (unsigned int i = 0; i < 6 * n; ++i)
        {
          slope_scale = std::max(slope_scale, std::abs(dl[i]));
          fe_jump = std::max(fe_jump, std::abs(dl[i] - dr[i]));
          smoothed_jump = std::max(smoothed_jump, std::abs(hl[i] - hr[i]));
        }
    }
  std::cout << "largest slope " << slope_scale << "; slope jump at vertices: FE " << fe_jump << ", smoothed "
            << smoothed_jump << "\n";
  const double h = data.length() / data.n_cells();
  EXPECT_LE(smoothed_error, (4 * 0.25 / 27) * h * fe_jump / 2 * (1 + 1e-9) + 1e-12 * largest);
  EXPECT_GT(fe_jump, 1e-9 * slope_scale); // the FE field really is only C0 ...
  EXPECT_LT(smoothed_jump, 1e-6 * slope_scale); // ... the smoothed field is C1 (up to the 1e-9 L offset)
  try
    {
      smoothed.evaluate(data.length() * (1 + 1e-9), v.data(), d.data());
      FAIL() << "no error off the arm";
    }
  catch (const std::out_of_range &e)
    {
      EXPECT_NE(std::string(e.what()).find("off arm 'boom'"), std::string::npos) << e.what();
    }
}
