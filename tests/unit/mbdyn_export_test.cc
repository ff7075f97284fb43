// MBDyn export (issue 5): a strict reader of the modal element data file (.fem) that enforces
// the rules of the MBDyn input manual, appendix "Modal Element Data / FEM File Format", as
// confirmed by running MBDyn (see doc/exports.md): it rejects any deviation. The record groups
// 8, 9, 10, 12 and 14-18 read from an exported file are recomputed from the FE model and the
// reduced basis by independent formulas (cross-product operators on the full model's nodal
// fields and its consistent mass matrix) and must agree to 1e-12 relative.
#include <fem/body_model.h>
#include <io/body_scene.h>
#include <base/input_error.h>
#include <io/mbdyn_export.h>
#include <io/reduced_body_file.h>
#include <reduction/component_modes.h>
#include <reduction/reduced_body_builder.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

using namespace flextrack;
using dealii::Tensor;
using dealii::Vector;

namespace
{
/// The content of a .fem file, read strictly.
struct FemFile
{
  unsigned int n_nodes = 0, n_modes = 0;
  std::vector<std::string> labels;
  std::map<int, std::vector<double>> groups; // record group -> numbers in file order
};

[[noreturn]] void reject(const unsigned int line, const std::string &why)
{
  throw std::runtime_error("line " + std::to_string(line) + ": " + why);
}

double strict_number(const std::string &token, const unsigned int line)
{
  if (token.find_first_of("dD") != std::string::npos) reject(line, "Fortran exponent in '" + token + "'");
  char *end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size() || !std::isfinite(v)) reject(line, "'" + token + "' is not a C++ double");
  return v;
}

FemFile read_fem_strictly(const std::string &text)
{
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  for (unsigned int i = 0; i < lines.size(); ++i)
    if (lines[i].size() >= 8192) reject(i + 1, "longer than MBDyn's 8192-byte line buffer");
  auto is_marker = [](const std::string &l) { return l.rfind("** RECORD GROUP ", 0) == 0; };
  auto is_end = [](const std::string &l) { return l.rfind("** END OF FILE", 0) == 0; };

  FemFile fem;
  unsigned int i = 0;
  // Tokens of data lines from line i on; a comment, marker or the end before count is an error.
  auto read_tokens = [&](const std::size_t count) {
    std::vector<std::string> tokens;
    while (tokens.size() < count)
      {
        if (i >= lines.size()) reject(i, "file ends inside a record group");
        const std::string &l = lines[i];
        if (l.rfind("**", 0) == 0) reject(i + 1, "comment or marker where data are expected");
        std::istringstream words(l);
        for (std::string w; words >> w;) tokens.push_back(w);
        if (tokens.size() > count) reject(i + 1, "more values than the record group holds");
        ++i;
      }
    return tokens;
  };
  auto read_numbers = [&](const std::size_t count) {
    const unsigned int first = i + 1;
    std::vector<double> v;
    for (const auto &t : read_tokens(count)) v.push_back(strict_number(t, first));
    return v;
  };

  // Nothing but the RG 1 marker may come first.
  if (lines.empty() || lines[0].rfind("** RECORD GROUP 1,", 0) != 0) reject(1, "the file must start with RECORD GROUP 1");
  bool ended = false;
  while (i < lines.size())
    {
      const std::string &l = lines[i];
      if (is_end(l))
        {
          ended = true;
          if (i + 1 != lines.size()) reject(i + 2, "text after END OF FILE");
          break;
        }
      if (!is_marker(l)) reject(i + 1, "expected a RECORD GROUP marker, found '" + l.substr(0, 40) + "'");
      const int group = std::atoi(l.c_str() + 16);
      if (fem.groups.count(group) || (group == 2 && !fem.labels.empty())) reject(i + 1, "record group repeated");
      ++i;
      const std::size_t N = fem.n_nodes, n = fem.n_modes;
      switch (group)
        {
          case 1:
            {
              // Exactly one comment line, then the six header tokens.
              if (i >= lines.size() || lines[i].rfind("**", 0) != 0) reject(i + 1, "RG 1 needs exactly one comment line");
              ++i;
              const auto h = read_tokens(6);
              const int nodes = std::stoi(h[1]), normal = std::stoi(h[2]), attached = std::stoi(h[3]),
                        constraint = std::stoi(h[4]), rejected = std::stoi(h[5]);
              fem.n_nodes = nodes;
              fem.n_modes = normal + attached + constraint - rejected;
              fem.groups[1] = {};
              break;
            }
          case 2:
            fem.labels = read_tokens(N);
            fem.groups[2] = {};
            break;
          case 5: case 6: case 7: fem.groups[group] = read_numbers(N); break;
          case 8:
            for (std::size_t k = 0; k < n; ++k)
              {
                // One header line per mode, empty or a comment (not a marker).
                if (i >= lines.size() || !(lines[i].empty() || lines[i].rfind("**", 0) == 0) || is_marker(lines[i]))
                  reject(i + 1, "mode " + std::to_string(k + 1) + " lacks its header line");
                ++i;
                const auto v = read_numbers(6 * N);
                fem.groups[8].insert(fem.groups[8].end(), v.begin(), v.end());
              }
            break;
          case 9: case 10: case 13: fem.groups[group] = read_numbers(n * n); break;
          case 11: fem.groups[11] = read_numbers(6 * N); break;
          case 12: fem.groups[12] = read_numbers(13); break;
          case 14: case 15: fem.groups[group] = read_numbers(3 * n); break;
          case 16: fem.groups[16] = read_numbers(9 * n); break;
          case 17: fem.groups[17] = read_numbers(3 * n * n); break;
          case 18: fem.groups[18] = read_numbers(9 * n * n); break;
          default: reject(i, "unknown record group " + std::to_string(group));
        }
    }
  if (!ended) reject(lines.size(), "no END OF FILE line");
  for (const int g : {1, 5, 6, 7, 8, 9, 10})
    if (!fem.groups.count(g) && !(g == 8 && fem.n_modes == 0)) reject(0, "mandatory record group " + std::to_string(g) + " missing");
  if (fem.labels.size() != fem.n_nodes) reject(0, "record group 2 missing");
  if (fem.groups.count(11))
    for (const int g : {14, 15, 16, 17, 18})
      if (fem.groups.count(g)) reject(0, "record group 11 together with 14-18: MBDyn would add them");
  return fem;
}

const std::string bracket =
  "set Model = body\nsubsection Body\n set Arms = boom\n set Ties = boom: rigid, within 0.03\n"
  " set Interfaces = tip: arm boom at 0.6; side: point 0.2 0.05 0.1, within 0.03\n"
  " set Point masses = tip: 0.3, 1e-4, 2e-4, 3e-4\n"
  " set Output points = mid: arm boom at 0.3; corner: point 0.2 0.1 0.1, within 0.03\nend\n"
  "subsection Solid\n set Mesh = box\n set Supports =\n subsection Box\n  set Size = 0.2, 0.1, 0.1\n"
  "  set Cells = 4, 2, 2\n end\nend\n"
  "subsection Arm boom\n subsection Curve\n  set Kind = line\n  subsection Line\n   set Start point = 0.2, 0.05, 0.05\n"
  "   set End point = 0.8, 0.05, 0.05\n  end\n end\n subsection Supports\n  set Start = free\n end\n"
  " subsection Mesh\n  set Number of elements = 12\n end\nend\n"
  "subsection Reduction\n set Number of normal modes = 5\n set Track arms = boom\n set Track stations = 2\n"
  " set Damping ratio = 0.02\nend\n";

double relative_difference(const std::vector<double> &a, const std::vector<double> &b)
{
  EXPECT_EQ(a.size(), b.size());
  double diff = 0, scale = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    {
      diff = std::max(diff, std::abs(a[i] - b[i]));
      scale = std::max(scale, std::abs(b[i]));
    }
  return scale > 0 ? diff / scale : diff;
}
} // namespace

TEST(MbdynExport, fem_file_passes_the_strict_reader_and_matches_the_fe_model)
{
  const auto scene = io::read_body_scene_from_string(bracket);
  const fem::BodyModel model(scene.body);
  const auto basis = reduction::reduce(model, scene.reduction);
  // Through the file, as a user would: reduce -> HDF5 -> export.
  const auto dir = std::filesystem::temp_directory_path() / ("flextrack_fem_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  io::write_reduced_body(reduction::make_reduced_body(model, basis, scene.reduction.method_name()), (dir / "b.h5").string());
  const auto body = io::read_reduced_body((dir / "b.h5").string());
  std::filesystem::remove_all(dir);
  const std::string text = io::mbdyn_fem_text(body);
  const FemFile fem = read_fem_strictly(text);
  const unsigned int n = basis.modes.size();
  ASSERT_EQ(fem.n_modes, n);
  ASSERT_EQ(fem.n_nodes, 4u); // 2 interfaces, then 2 output points
  EXPECT_EQ(fem.labels, (std::vector<std::string>{"tip", "side", "mid", "corner"}));

  // Independent recomputation on the full model (translation fields, consistent mass).
  const auto &nodes = model.full_nodes();
  std::vector<Vector<double>> phi;
  for (const auto &m : basis.modes) phi.push_back(model.expand(m));
  const unsigned int n_full = model.n_full_dofs();
  auto field = [&](auto &&translation, auto &&rotation) {
    Vector<double> v(n_full);
    for (const auto &node : nodes)
      {
        const Tensor<1, 3> t = translation(node), r = rotation(node);
        for (unsigned int d = 0; d < 3; ++d)
          {
            v[node.u[d]] = t[d];
            if (node.theta[d] >= 0) v[node.theta[d]] = r[d];
          }
      }
    return v;
  };
  auto zero = [](const auto &) { return Tensor<1, 3>(); };
  auto e = [](const unsigned int a) { return Tensor<1, 3>(dealii::Point<3>::unit_vector(a)); };
  auto mode_at = [&](const unsigned int k, const fem::BodyModel::Node &node) {
    return Tensor<1, 3>({phi[k][node.u[0]], phi[k][node.u[1]], phi[k][node.u[2]]});
  };
  auto mass_product = [&](const Vector<double> &a, const Vector<double> &b) {
    Vector<double> Mb(n_full);
    model.full_mass_vmult(Mb, b);
    return a * Mb;
  };

  // RG 8: mode shapes at the interfaces (body dofs) and the output points (through T).
  std::vector<double> rg8;
  for (unsigned int k = 0; k < n; ++k)
    {
      for (const auto &p : model.interfaces())
        for (unsigned int c = 0; c < 6; ++c) rg8.push_back(basis.modes[k][p.dofs[c]]);
      for (const auto &p : model.output_points())
        for (unsigned int c = 0; c < 6; ++c) rg8.push_back(phi[k][p.full_dofs[c]]);
    }
  EXPECT_LT(relative_difference(fem.groups.at(8), rg8), 1e-15);
  // The arm output point's translation is the beam model's own displacement at s = 0.3 m.
  for (unsigned int k = 0; k < n; ++k)
    {
      const auto u = model.arm_displacement(0, 0.3, basis.modes[k]);
      for (unsigned int c = 0; c < 3; ++c)
        EXPECT_NEAR(fem.groups.at(8)[(k * 4 + 2) * 6 + c], u[c], 1e-12 * (1 + u.norm()));
    }
  // RG 9, 10: Phi^T M Phi, Phi^T K Phi on the body's matrices.
  std::vector<double> rg9, rg10;
  Vector<double> Mv(model.n_dofs()), Kv(model.n_dofs());
  for (unsigned int a = 0; a < n; ++a)
    {
      model.mass_matrix().vmult(Mv, basis.modes[a]);
      model.stiffness_matrix().vmult(Kv, basis.modes[a]);
      for (unsigned int b = 0; b < n; ++b)
        {
          rg9.push_back(basis.modes[b] * Mv);
          rg10.push_back(basis.modes[b] * Kv);
        }
    }
  EXPECT_LT(relative_difference(fem.groups.at(9), rg9), 1e-12);
  EXPECT_LT(relative_difference(fem.groups.at(10), rg10), 1e-12);
  // RG 12: rigid-body inertia from the six rigid motions of the full model.
  std::vector<Vector<double>> R;
  for (unsigned int a = 0; a < 3; ++a) R.push_back(field([&](const auto &) { return e(a); }, zero));
  for (unsigned int a = 0; a < 3; ++a)
    R.push_back(field([&](const auto &node) { return cross_product_3d(e(a), Tensor<1, 3>(node.x)); },
                      [&](const auto &) { return e(a); }));
  const double m = mass_product(R[0], R[0]);
  const Tensor<1, 3> s({mass_product(R[1], R[5]), mass_product(R[2], R[3]), mass_product(R[0], R[4])}); // m c
  const Tensor<1, 3> c = s / m;
  std::vector<double> rg12{m, c[0], c[1], c[2]};
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int b = 0; b < 3; ++b)
      rg12.push_back(mass_product(R[3 + a], R[3 + b]) - m * ((a == b ? c * c : 0.0) - c[a] * c[b]));
  EXPECT_LT(relative_difference(fem.groups.at(12), rg12), 1e-12);
  // RG 14, 15: int rho Phi and int rho x~ Phi (+ rotary inertia).
  std::vector<double> rg14, rg15;
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int k = 0; k < n; ++k)
      {
        rg14.push_back(mass_product(R[a], phi[k]));
        rg15.push_back(mass_product(R[3 + a], phi[k]));
      }
  EXPECT_LT(relative_difference(fem.groups.at(14), rg14), 1e-12);
  EXPECT_LT(relative_difference(fem.groups.at(15), rg15), 1e-12);
  // Cross-product operators on translations: X_a(v) = e_a x v, rotations zero.
  auto X = [&](const unsigned int a, auto &&v) {
    return field([&](const auto &node) { return cross_product_3d(e(a), v(node)); }, zero);
  };
  auto position = [](const fem::BodyModel::Node &node) { return Tensor<1, 3>(node.x); };
  // RG 16: I8_j(a, b) = (e_a x x)^T M (e_b x phi_j); rows a, then j, then b.
  std::vector<double> rg16(9 * n);
  for (unsigned int j = 0; j < n; ++j)
    for (unsigned int b = 0; b < 3; ++b)
      {
        const auto Xb = X(b, [&](const auto &node) { return mode_at(j, node); });
        for (unsigned int a = 0; a < 3; ++a) rg16[a * 3 * n + 3 * j + b] = mass_product(X(a, position), Xb);
      }
  EXPECT_LT(relative_difference(fem.groups.at(16), rg16), 1e-12);
  // RG 17: I5_jk[a] = (e_a x phi_j)^T M phi_k; RG 18: I9_jk(a, b) = -(e_a x phi_j)^T M (e_b x phi_k).
  std::vector<double> rg17(3 * n * n), rg18(9 * n * n);
  for (unsigned int j = 0; j < n; ++j)
    for (unsigned int a = 0; a < 3; ++a)
      {
        const auto Xa = X(a, [&](const auto &node) { return mode_at(j, node); });
        for (unsigned int k = 0; k < n; ++k)
          {
            const auto Pk = field([&](const auto &node) { return mode_at(k, node); }, zero);
            rg17[a * n * n + j * n + k] = mass_product(Xa, Pk);
            for (unsigned int b = 0; b < 3; ++b)
              rg18[a * 3 * n * n + (j * n + k) * 3 + b] =
                -mass_product(Xa, X(b, [&](const auto &node) { return mode_at(k, node); }));
          }
      }
  EXPECT_LT(relative_difference(fem.groups.at(17), rg17), 1e-12);
  EXPECT_LT(relative_difference(fem.groups.at(18), rg18), 1e-12);
  std::cout << "strict reader: " << n << " modes, 4 nodes; RG 8, 9, 10, 12, 14-18 recomputed from the FE model\n";
}

TEST(MbdynExport, strict_reader_rejects_deviations_from_the_manual)
{
  // The reader must fail on each rule a writer has to respect (doc/exports.md), so that the
  // test above can only pass on a conforming file.
  const auto scene = io::read_body_scene_from_string(bracket);
  const fem::BodyModel model(scene.body);
  const auto body = reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), "craig bampton");
  const std::string good = io::mbdyn_fem_text(body);
  EXPECT_NO_THROW(read_fem_strictly(good));
  auto replaced = [&](const std::string &from, const std::string &to) {
    std::string t = good;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  const auto rg9 = good.find("** RECORD GROUP 9");
  const auto rg9_end = good.find('\n', rg9) + 1;
  std::map<std::string, std::string> bad{
    {"comment after the RG 9 marker", std::string(good).insert(rg9_end, "** a comment\n")},
    {"Fortran D exponent", std::string(good).replace(good.find('e', rg9_end), 1, "D")},
    {"mode without a header line", replaced("**    NORMAL MODE SHAPE # 2\n", "")},
    {"RG 11 with RG 14-18",
     replaced("** RECORD GROUP 12", "** RECORD GROUP 11, LUMPED MASSES\n1 1 1 1 1 1\n1 1 1 1 1 1\n** RECORD GROUP 12")},
    {"line over 8 KB", std::string(good).insert(rg9_end, std::string(9000, ' ') + "\n")},
    {"missing END OF FILE", replaced("** END OF FILE\n", "")},
    {"a line before the RG 1 marker", "** header\n" + good},
  };
  // A value missing from RG 10: drop the last number of its first line.
  {
    std::string t = good;
    const auto line = t.find('\n', t.find("** RECORD GROUP 10")) + 1;
    const auto line_end = t.find('\n', line);
    const auto last_blank = t.rfind(' ', line_end);
    t.erase(last_blank, line_end - last_blank);
    bad["a value missing from RG 10"] = t;
  }
  // "no comment after RG 1": remove that line outright.
  {
    std::string t = good;
    const auto at = t.find("**   REVISION");
    t.erase(at, t.find('\n', at) + 1 - at);
    bad["no comment after the RG 1 marker"] = t;
  }
  for (const auto &[what, text] : bad)
    {
      bool rejected = false;
      try
        {
          read_fem_strictly(text);
        }
      catch (const std::exception &e)
        {
          rejected = true;
          std::cout << what << ": rejected (" << e.what() << ")\n";
        }
      EXPECT_TRUE(rejected) << what;
    }
}

TEST(MbdynExport, rigid_limit_body_exports_the_analytic_inertia)
{
  // A free box 1.2 x 0.5 x 0.3 m reduced to zero modes: RG 12 holds m = rho a b c, the centre
  // (a, b, c) / 2 and J = m / 12 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2) to 1e-12 (issue 5).
  const auto scene = io::read_body_scene_from_string(
    "set Model = body\nsubsection Solid\n set Mesh = box\n set Supports =\n subsection Box\n"
    "  set Size = 1.2, 0.5, 0.3\n  set Cells = 4, 3, 2\n end\nend\nsubsection Reduction\n"
    " set Method = free interface\n set Number of normal modes = 0\nend\n");
  const fem::BodyModel model(scene.body);
  const auto body = reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), "free interface");
  ASSERT_EQ(body.n_modes(), 0u);
  const FemFile fem = read_fem_strictly(io::mbdyn_fem_text(body));
  const auto &g = fem.groups.at(12);
  const double a = 1.2, b = 0.5, c = 0.3, m = 7850 * a * b * c;
  EXPECT_NEAR(g[0], m, 1e-12 * m);
  EXPECT_NEAR(g[1], a / 2, 1e-12 * a);
  EXPECT_NEAR(g[2], b / 2, 1e-12 * a);
  EXPECT_NEAR(g[3], c / 2, 1e-12 * a);
  const double J[3] = {m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12};
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j) EXPECT_NEAR(g[4 + 3 * i + j], i == j ? J[i] : 0.0, 1e-12 * J[0]) << i << j;
}

TEST(MbdynExport, refuses_a_body_whose_inertia_is_not_positive_definite)
{
  // A straight rod modelled without rotary inertia has no inertia about its axis: MBDyn fails
  // on such a body, so the export is refused with the reason. (A point mass alone, J = 0.)
  reduction::ReducedBody body;
  body.invariants.mass = 1;
  body.invariants.first_moment = Tensor<1, 3>({0, 0, 0});
  body.invariants.inertia_origin[1][1] = body.invariants.inertia_origin[2][2] = 1; // J_xx = 0
  try
    {
      io::mbdyn_fem_text(body);
      FAIL() << "no error";
    }
  catch (const InputError &e)
    {
      EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
    }
}
