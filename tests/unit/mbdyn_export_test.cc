// MBDyn export (issue 5): a strict reader of the modal element data file (.fem) that enforces
// the rules of the MBDyn input manual, appendix "Modal Element Data / FEM File Format", as
// confirmed by running MBDyn (see doc/exports.md): it rejects any deviation. The record groups
// 8, 9, 10, 12 and 14-18 read from an exported file are recomputed from the FE model and the
// reduced basis by independent formulas (cross-product operators on the full model's nodal
// fields and its consistent mass matrix) and must agree to 1e-12 relative.
//
// Issue 13: a strict parser of the .elm include file that follows the modal joint syntax of the
// MBDyn input manual (section "Modal" of the joints: reference node, mode count, optional list and
// initial values, FEM node count or 'from file', optional damping, the quoted FEM file name,
// optional threshold/binary/echo/invariant/origin items, interface count, interfaces) and the
// clamp joint (node, position, orientation); it rejects the statement that MBDyn rejected (no
// 'from file' before 'damping from file'). Record groups 9, 10 and 13 are exactly symmetric and,
// for a mass-orthonormal basis, diagonal.
//
// Issue 28: the clamp of the modal node as an option of the export (io::MbdynClamp: auto, yes,
// no); the .elm of each choice passes the strict parser with the clamp written or left out, and
// states the joint count that goes with it.
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
#include <regex>
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


// ---------------------------------------------------------------------------------------------
// A strict reader of MBDyn input text (the statements an include file for the elements block may
// hold): '#' comments to the end of a line and C comments; statements end at ';'; a statement is
// "description: fields", fields separated by ',' (quotes protect both). Multi-word keywords are
// compared with their blanks collapsed.

struct MbdynStatement
{
  std::string description;          ///< before the first ':'
  std::vector<std::string> fields;  ///< trimmed, inner blanks collapsed to one
};

std::vector<MbdynStatement> mbdyn_statements(const std::string &text)
{
  // Remove comments outside strings.
  std::string clean;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i)
    {
      const char c = text[i];
      if (in_string)
        {
          if (c == '\n') throw std::runtime_error("a string runs past the end of its line");
          in_string = c != '"';
          clean += c;
        }
      else if (c == '"')
        in_string = true, clean += c;
      else if (c == '#')
        {
          while (i < text.size() && text[i] != '\n') ++i;
          clean += '\n';
        }
      else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*')
        {
          const auto end = text.find("*/", i + 2);
          if (end == std::string::npos) throw std::runtime_error("unterminated C comment");
          i = end + 1;
          clean += ' ';
        }
      else
        clean += c;
    }
  if (in_string) throw std::runtime_error("unterminated string");
  auto collapse = [](const std::string &f) {
    std::string r;
    std::istringstream words(f);
    for (std::string w; words >> w;) r += (r.empty() ? "" : " ") + w;
    return r;
  };
  std::vector<MbdynStatement> statements;
  std::string current;
  in_string = false;
  for (const char c : clean)
    {
      if (c == '"') in_string = !in_string;
      if (c != ';' || in_string)
        {
          current += c;
          continue;
        }
      const auto colon = current.find(':');
      if (colon == std::string::npos) throw std::runtime_error("statement without ':': '" + collapse(current) + "'");
      MbdynStatement st{collapse(current.substr(0, colon)), {}};
      std::string field;
      bool quoted = false;
      for (const char d : current.substr(colon + 1) + ",")
        {
          if (d == '"') quoted = !quoted;
          if (d == ',' && !quoted)
            {
              st.fields.push_back(collapse(field));
              field.clear();
            }
          else
            field += d;
        }
      for (const auto &f : st.fields)
        if (f.empty()) throw std::runtime_error("empty field in '" + st.description + ":' statement");
      statements.push_back(st);
      current.clear();
    }
  if (!collapse(current).empty()) throw std::runtime_error("text after the last ';': '" + collapse(current) + "'");
  return statements;
}

/// The modal joint as read by the grammar of the manual.
struct ModalJoint
{
  long long label = 0, node = -1; ///< node -1: 'clamped'
  long long modes = 0;
  bool nodes_from_file = false;
  std::string damping; ///< the damping keyword, or empty
  std::string file;
  std::string origin; ///< 'origin node' / 'origin position', or empty
  struct Attachment
  {
    std::string fem_label;
    long long multibody_node = 0;
  };
  std::vector<Attachment> interfaces;
};

struct ClampJoint
{
  long long label = 0, node = 0;
};

/// Reads the statements of an .elm file: 'set: integer NAME = VALUE' definitions, modal joints
/// and clamp joints, each field in the order of the manual's syntax; anything else is an error.
struct ElmFile
{
  std::map<std::string, long long> integers;
  std::vector<ModalJoint> modal;
  std::vector<ClampJoint> clamps;
};

ElmFile read_elm_strictly(const std::string &text)
{
  ElmFile elm;
  for (const auto &st : mbdyn_statements(text))
    {
      const std::string where = "'" + st.description + ": " + (st.fields.empty() ? "" : st.fields[0]) + ", ...'";
      auto fail = [&](const std::string &why) -> void { throw std::runtime_error(where + ": " + why); };
      if (st.description == "set")
        {
          std::smatch m;
          // [ifndef] [const] integer NAME = VALUE (manual, "set"); 'ifndef' keeps an existing name.
          static const std::regex integer_set(R"((ifndef )?(const )?integer ([A-Za-z_][A-Za-z0-9_]*) = (-?[0-9]+))");
          if (st.fields.size() != 1 || !std::regex_match(st.fields[0], m, integer_set))
            fail("not '[ifndef] [const] integer NAME = VALUE'");
          if (elm.integers.count(m[3]) && !m[1].matched) fail("'" + std::string(m[3]) + "' set twice");
          elm.integers.emplace(m[3], std::stoll(m[4]));
          continue;
        }
      if (st.description != "joint") fail("not a 'set:' or 'joint:' statement");
      std::size_t i = 0;
      auto at_end = [&] { return i >= st.fields.size(); };
      auto peek = [&]() -> std::string { return at_end() ? std::string("<end of statement>") : st.fields[i]; };
      auto next = [&](const std::string &what) {
        if (at_end()) fail(what + " expected, the statement ends");
        return st.fields[i++];
      };
      auto is_integer_literal = [](const std::string &f) { return std::regex_match(f, std::regex("-?[0-9]+")); };
      auto integer = [&](const std::string &what) {
        const std::string f = next(what);
        if (is_integer_literal(f)) return std::stoll(f);
        if (elm.integers.count(f)) return elm.integers.at(f);
        fail(what + " (an integer or a 'set: integer' name) expected, found '" + f + "'");
        return 0LL;
      };
      auto real = [&](const std::string &what) {
        const std::string f = next(what);
        char *end = nullptr;
        const double v = std::strtod(f.c_str(), &end);
        if (f.empty() || end != f.c_str() + f.size()) fail(what + " (a number) expected, found '" + f + "'");
        return v;
      };
      auto keyword = [&](const std::string &k) {
        if (peek() != k) return false;
        ++i;
        return true;
      };
      auto vec3 = [&](const std::string &what) {
        if (keyword("null")) return;
        for (int c = 0; c < 3; ++c) real(what);
      };
      auto orientation = [&](const std::string &what) {
        if (keyword("eye")) return;
        for (int c = 0; c < 9; ++c) real(what);
      };
      const long long label = integer("joint label");
      const std::string type = next("joint type");
      if (type == "clamp")
        {
          ClampJoint c{label, integer("node label")};
          keyword("position");
          if (!keyword("node")) vec3("absolute position");
          keyword("orientation");
          if (!keyword("node")) orientation("absolute orientation");
          if (!at_end()) fail("'" + peek() + "' after the clamp's orientation");
          elm.clamps.push_back(c);
          continue;
        }
      if (type != "modal") fail("joint type '" + type + "' is neither 'modal' nor 'clamp'");
      ModalJoint j;
      j.label = label;
      // { reference_modal_node | clamped [, position, Vec3] [, orientation, OrientationMatrix] }
      if (keyword("clamped"))
        {
          if (keyword("position")) vec3("absolute position");
          if (keyword("orientation")) orientation("absolute orientation");
        }
      else
        j.node = integer("reference modal node");
      j.modes = integer("mode number");
      if (j.modes <= 0) fail("mode number must be positive");
      if (keyword("list"))
        for (long long k = 0; k < j.modes; ++k) integer("active mode");
      if (keyword("initial value"))
        {
          if (peek() == "mode")
            while (keyword("mode"))
              {
                integer("mode index");
                real("q_j");
                real("qP_j");
              }
          else
            for (long long k = 0; k < 2 * j.modes; ++k) real("initial value");
        }
      // { FEM_node_number | from file }
      if (keyword("from file"))
        j.nodes_from_file = true;
      else if (is_integer_literal(peek()) || elm.integers.count(peek()))
        integer("FEM node number");
      else
        fail("the FEM node number or 'from file' expected after the mode count, found '" + peek() + "'");
      // [ damping ]
      if (keyword("no damping") || keyword("damping from file"))
        j.damping = st.fields[i - 1];
      else if (keyword("rayleigh damping"))
        {
          j.damping = "rayleigh damping";
          real("mass damping coefficient");
          real("stiffness damping coefficient");
        }
      else if (keyword("single factor damping"))
        {
          j.damping = "single factor damping";
          real("damping factor");
        }
      else if (keyword("diag damping"))
        {
          j.damping = "diag damping";
          if (keyword("all"))
            for (long long k = 0; k < j.modes; ++k) real("damping factor");
          else
            for (long long k = integer("number of damped modes"); k > 0; --k)
              {
                integer("mode index");
                real("damping factor");
              }
        }
      // " FEM_data_file "
      {
        const std::string f = next("the quoted FEM data file");
        if (f.size() < 2 || f.front() != '"' || f.back() != '"')
          fail("the quoted FEM data file expected, found '" + f + "'");
        j.file = f.substr(1, f.size() - 2);
      }
      for (const char *k : {"threshold", "mass threshold", "damping threshold", "stiffness threshold"})
        if (keyword(k)) real("threshold");
      while (keyword("create binary") || keyword("use binary") || keyword("update binary")) {}
      if (keyword("echo"))
        {
          next("echo file");
          if (keyword("precision")) integer("precision");
        }
      keyword("use invariant 9");
      if (keyword("origin node"))
        {
          j.origin = "origin node";
          integer("origin node");
        }
      else if (keyword("origin position"))
        {
          j.origin = "origin position";
          vec3("origin position");
        }
      const long long count = integer("interface nodes number");
      if (count < 0) fail("negative interface count");
      if (keyword("output")) next("output flag");
      if (keyword("interface tolerance")) real("interface tolerance");
      for (long long k = 0; k < count; ++k)
        {
          ModalJoint::Attachment a;
          const std::string fem = next("FEM node label");
          if (fem == "find closest")
            {
              if (keyword("interface tolerance")) real("interface tolerance");
            }
          else if (fem.size() >= 2 && fem.front() == '"' && fem.back() == '"')
            {
              a.fem_label = fem.substr(1, fem.size() - 2);
              if (a.fem_label.empty() || a.fem_label.find_first_of(" \t") != std::string::npos)
                fail("FEM label '" + a.fem_label + "' is empty or has blanks");
            }
          else if (is_integer_literal(fem))
            a.fem_label = fem;
          else
            fail("FEM node label (a quoted string, an integer or 'find closest') expected, found '" + fem + "'");
          a.multibody_node = integer("multibody node label");
          vec3("offset of the FEM node");
          if (keyword("output")) next("output flag");
          j.interfaces.push_back(a);
        }
      if (!at_end()) fail("'" + peek() + "' after the " + std::to_string(count) + " interface nodes");
      elm.modal.push_back(j);
    }
  return elm;
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


namespace
{
/// The bracket body, supported ('with_supports': the solid's XMIN face clamped) or free, reduced
/// by @p method.
reduction::ReducedBody bracket_body(const bool with_supports, const std::string &method = "craig bampton")
{
  std::string text = bracket;
  if (with_supports) text.replace(text.find(" set Supports =\n"), 16, " set Supports = XMIN: x, y, z\n");
  if (method != "craig bampton") text += "subsection Reduction\n set Method = " + method + "\nend\n";
  const auto scene = io::read_body_scene_from_string(text);
  const fem::BodyModel model(scene.body);
  return reduction::make_reduced_body(model, reduction::reduce(model, scene.reduction), scene.reduction.method_name());
}

std::string parse_error(const std::string &text)
{
  try
    {
      read_elm_strictly(text);
    }
  catch (const std::exception &e)
    {
      return e.what();
    }
  return "";
}
} // namespace

TEST(MbdynExport, elm_modal_joint_follows_the_manuals_token_order)
{
  // The free bracket (Craig-Bampton, held at its first interface 'tip'): one modal joint whose
  // fields are, in the manual's order, the modal node, the mode count, 'from file', 'damping from
  // file', the .fem name, the interface count and the interfaces; the FEM labels are those of
  // the .fem file's record group 2 and every multibody label is defined by a 'set:'.
  const auto body = bracket_body(false);
  ASSERT_EQ(io::mbdyn_support(body), io::MbdynSupport::free_at_first_interface);
  const std::string text = io::mbdyn_elm_text(body, "bracket.fem");
  const ElmFile elm = read_elm_strictly(text);
  ASSERT_EQ(elm.modal.size(), 1u);
  EXPECT_TRUE(elm.clamps.empty()) << "a free body's modal node must not be clamped";
  const ModalJoint &j = elm.modal[0];
  EXPECT_EQ(j.label, 1000);
  EXPECT_EQ(j.node, elm.integers.at("flextrack_modal_node"));
  EXPECT_EQ(j.modes, static_cast<long long>(body.n_modes()));
  EXPECT_TRUE(j.nodes_from_file);
  EXPECT_EQ(j.damping, "damping from file");
  EXPECT_EQ(j.file, "bracket.fem");
  EXPECT_EQ(j.origin, "") << "the modal node stays at the body-frame origin";
  const FemFile fem = read_fem_strictly(io::mbdyn_fem_text(body));
  ASSERT_EQ(j.interfaces.size(), 2u);
  std::set<long long> nodes;
  for (unsigned int i = 0; i < j.interfaces.size(); ++i)
    {
      EXPECT_EQ(j.interfaces[i].fem_label, body.interfaces[i].name);
      EXPECT_NE(std::find(fem.labels.begin(), fem.labels.end(), j.interfaces[i].fem_label), fem.labels.end());
      EXPECT_EQ(j.interfaces[i].multibody_node, elm.integers.at("flextrack_node_" + body.interfaces[i].name));
      nodes.insert(j.interfaces[i].multibody_node);
    }
  EXPECT_EQ(nodes.size(), 2u);
  EXPECT_EQ(nodes.count(j.node), 0u) << "an interface node may not be the modal node";
  // The comment names the interface positions exactly (shortest text that reads back the same).
  for (const auto &p : body.interfaces)
    {
      const auto at = text.find("flextrack_node_" + p.name + " = ");
      ASSERT_NE(at, std::string::npos);
      std::smatch m;
      const std::string line = text.substr(at, text.find('\n', at) - at);
      ASSERT_TRUE(std::regex_search(line, m, std::regex(R"(# at \(([^,]+), ([^,]+), ([^)]+)\) m)"))) << line;
      for (unsigned int d = 0; d < 3; ++d) EXPECT_EQ(std::stod(m[d + 1]), p.position[d]) << line;
    }
}

TEST(MbdynExport, elm_parser_rejects_the_statement_mbdyn_rejected)
{
  // Issue 13: the statement written before had the mode count followed by 'damping from file';
  // MBDyn read that as the FEM node count and aborted. The parser must refuse it, and the other
  // deviations from the manual's order, so that the test above can only pass on a valid file.
  const std::string good = io::mbdyn_elm_text(bracket_body(false), "bracket.fem");
  ASSERT_EQ(parse_error(good), "");
  auto without = [&](const std::string &line) {
    std::string t = good;
    const auto at = t.find(line);
    EXPECT_NE(at, std::string::npos) << line;
    return t.erase(at, line.size());
  };
  auto replaced = [&](const std::string &from, const std::string &to) {
    std::string t = good;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  const std::string from_file = "\tfrom file,  # FEM nodes: those of the .fem file\n";
  const std::string damping = "\tdamping from file,  # record group 13\n";
  const std::map<std::string, std::pair<std::string, std::string>> bad{
    {"the old statement (no 'from file')", {without(from_file), "'from file' expected after the mode count, found 'damping from file'"}},
    {"damping before 'from file'", {replaced(from_file + damping, damping + from_file), "found 'damping from file'"}},
    {"file name before the damping", {replaced(damping + "\t\"bracket.fem\",\n", "\t\"bracket.fem\",\n" + damping), "interface nodes number"}},
    {"file name not quoted", {replaced("\"bracket.fem\"", "bracket.fem"), "quoted FEM data file"}},
    {"one interface fewer than counted", {replaced("\t2,  # interface nodes", "\t3,  # interface nodes"), "expected, the statement ends"}},
    {"an undefined multibody label", {replaced("\"tip\", flextrack_node_tip", "\"tip\", flextrack_node_top"), "multibody node label"}},
    {"a label set twice without ifndef", {"set: integer a = 1;\n" + replaced("ifndef integer flextrack_modal_node", "integer a"), "set twice"}},
    {"a missing ';'", {replaced("null;\n", "null\n"), "after the last ';'"}},
  };
  for (const auto &[what, text_and_message] : bad)
    {
      const std::string error = parse_error(text_and_message.first);
      EXPECT_NE(error.find(text_and_message.second), std::string::npos) << what << ": " << (error.empty() ? "accepted" : error);
      std::cout << what << ": " << error << "\n";
    }
  // The manual's own example (section "Modal", output) is accepted.
  EXPECT_EQ(parse_error("set: integer MODAL_ELEM = 99;\nset: integer MODAL_NODE = 101;\n"
                        "joint: MODAL_ELEM, modal, MODAL_NODE,\n 3, list, 1, 7, 9, # only some modes\n from file,\n"
                        " \"modal.fem\",\n 0;                # no FEM nodes\n"),
            "");
}

TEST(MbdynExport, supported_body_gets_a_clamp_of_its_modal_node)
{
  // Issue 13, item 3: the bracket with its XMIN face clamped. Its modes are those of the
  // supported body, so left free in MBDyn it would float away; the .elm clamps the modal node
  // (a second joint) where it stands. The free bracket's .elm only says how to add one.
  const auto body = bracket_body(true);
  EXPECT_EQ(io::mbdyn_support(body), io::MbdynSupport::supported);
  const ElmFile elm = read_elm_strictly(io::mbdyn_elm_text(body, "b.fem"));
  ASSERT_EQ(elm.clamps.size(), 1u);
  ASSERT_EQ(elm.modal.size(), 1u);
  EXPECT_EQ(elm.clamps[0].node, elm.modal[0].node);
  EXPECT_NE(elm.clamps[0].label, elm.modal[0].label) << "two joints need two labels";
  const std::string free_text = io::mbdyn_elm_text(bracket_body(false), "b.fem");
  EXPECT_TRUE(read_elm_strictly(free_text).clamps.empty());
  EXPECT_NE(free_text.find("# set: ifndef integer flextrack_clamp_joint = 1001;"), std::string::npos);
  EXPECT_NE(free_text.find("# joint: flextrack_clamp_joint, clamp, flextrack_modal_node, node, node;"), std::string::npos);
  // Free-interface reduction of the free bracket: mean axes.
  EXPECT_EQ(io::mbdyn_support(bracket_body(false, "free interface")), io::MbdynSupport::free_mean_axes);
  EXPECT_EQ(io::mbdyn_support(bracket_body(true, "free interface")), io::MbdynSupport::supported);
}

TEST(MbdynExport, reduced_matrices_are_written_exactly_symmetric_and_diagonal)
{
  // Issue 13, item 2: MBDyn compares M(i, j) with M(j, i) bit for bit and warns on any non-zero
  // off-diagonal term. The bases are mass-orthonormal, so record groups 9, 10 and 13 must come
  // out exactly symmetric and diagonal, the diagonal being the stored one; the terms set to 0 are
  // round-off: at most mbdyn_round_off_threshold sqrt(A_ii A_jj) (the largest is printed).
  for (const bool supported : {false, true})
    for (const std::string method : {"craig bampton", "free interface"})
      {
        const auto body = bracket_body(supported, method);
        const FemFile fem = read_fem_strictly(io::mbdyn_fem_text(body));
        const unsigned int n = body.n_modes();
        const std::map<int, const dealii::FullMatrix<double> *> stored{{9, &body.mass}, {10, &body.stiffness}, {13, &body.damping}};
        for (const auto &[group, A] : stored)
          {
            const auto &g = fem.groups.at(group);
            double largest_dropped = 0;
            for (unsigned int i = 0; i < n; ++i)
              {
                EXPECT_EQ(g[i * n + i], (*A)(i, i)) << "RG " << group;
                for (unsigned int j = 0; j < n; ++j)
                  if (i != j)
                    {
                      EXPECT_EQ(g[i * n + j], 0.0) << "RG " << group << " (" << i << ", " << j << ")";
                      largest_dropped = std::max(largest_dropped, std::abs((*A)(i, j)) / std::sqrt(std::abs((*A)(i, i) * (*A)(j, j))));
                    }
              }
            EXPECT_LE(largest_dropped, io::mbdyn_round_off_threshold);
            std::cout << (supported ? "supported, " : "free, ") << method << ", RG " << group
                      << ": largest off-diagonal |A_ij| / sqrt(A_ii A_jj) set to 0: " << largest_dropped << "\n";
          }
      }
}

TEST(MbdynExport, symmetric_part_keeps_real_coupling_and_drops_round_off_only)
{
  // Hand-made matrices. (a) A basis that is not mass-orthonormal: the symmetric part is written,
  // bit-for-bit symmetric, nothing dropped. (b) A mass-orthonormal basis: a stiffness coupling of
  // 1e-6 sqrt(K_ii K_jj) is real and stays; one of 1e-12 is round-off and goes.
  reduction::ReducedBody body;
  body.mass.reinit(3, 3);
  body.stiffness.reinit(3, 3);
  body.damping.reinit(3, 3);
  const double k[3] = {4e2, 9e6, 2.5e9};
  for (unsigned int i = 0; i < 3; ++i) body.mass(i, i) = 1, body.stiffness(i, i) = k[i], body.damping(i, i) = 1e-3 * k[i];
  body.mass(1, 0) = 0.1 + 3e-17;
  body.mass(0, 1) = 0.1;
  body.stiffness(2, 1) = 1e-12 * std::sqrt(k[1] * k[2]);
  body.stiffness(1, 2) = 1.3e-12 * std::sqrt(k[1] * k[2]);
  body.stiffness(0, 2) = body.stiffness(2, 0) = 1e-6 * std::sqrt(k[0] * k[2]);
  const auto a = io::mbdyn_matrices(body);
  EXPECT_FALSE(a.mass_orthonormal);
  for (const auto *A : {&a.mass, &a.stiffness, &a.damping})
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j) EXPECT_EQ((*A)(i, j), (*A)(j, i));
  EXPECT_EQ(a.mass(0, 1), 0.5 * (0.1 + (0.1 + 3e-17)));
  EXPECT_NE(a.stiffness(1, 2), 0.0) << "nothing dropped without a mass-orthonormal basis";
  body.mass(1, 0) = 3e-17;
  body.mass(0, 1) = -2e-17;
  const auto b = io::mbdyn_matrices(body);
  EXPECT_TRUE(b.mass_orthonormal);
  EXPECT_EQ(b.mass(0, 1), 0.0);
  EXPECT_EQ(b.mass(1, 0), 0.0);
  EXPECT_EQ(b.stiffness(1, 2), 0.0);
  EXPECT_EQ(b.stiffness(2, 1), 0.0);
  EXPECT_EQ(b.stiffness(0, 2), 1e-6 * std::sqrt(k[0] * k[2]));
  EXPECT_EQ(b.stiffness(2, 0), b.stiffness(0, 2));
  // A term just above the threshold stays, one at it goes.
  body.stiffness(1, 2) = body.stiffness(2, 1) = 1.01 * io::mbdyn_round_off_threshold * std::sqrt(k[1] * k[2]);
  EXPECT_NE(io::mbdyn_matrices(body).stiffness(1, 2), 0.0);
  body.stiffness(1, 2) = body.stiffness(2, 1) = 0.99 * io::mbdyn_round_off_threshold * std::sqrt(k[1] * k[2]);
  EXPECT_EQ(io::mbdyn_matrices(body).stiffness(1, 2), 0.0);
}

namespace
{
/// The number N of "count N joint(s) for this file" in an .elm comment, -1 if there is none.
int stated_joint_count(const std::string &elm)
{
  std::smatch m;
  if (!std::regex_search(elm, m, std::regex(R"(count ([0-9]+) joints? for this file)"))) return -1;
  return std::stoi(m[1]);
}

/// The text up to the end of the modal joint statement (the first "null;" line).
std::string up_to_the_modal_joint(const std::string &elm) { return elm.substr(0, elm.find(", null;\n") + 8); }
} // namespace

TEST(MbdynExport, clamp_option_writes_or_leaves_out_the_clamp_of_the_modal_node)
{
  // Issue 28: a body that hangs on a joint of the including model (the flexible pendulum) must
  // not have its modal node clamped (MBDyn stops with ENOPIV in the revolute pin). 'flextrack
  // export --mbdyn-clamp no' leaves the clamp out, 'yes' writes it for any body, 'auto' (the
  // default) is the behaviour of issue 13: a clamp exactly when the data show supports. Only the
  // end of the file changes; the joint count the comment states is that of the statements.
  const auto supported = bracket_body(true), free = bracket_body(false);
  ASSERT_EQ(io::mbdyn_support(supported), io::MbdynSupport::supported);
  ASSERT_EQ(io::mbdyn_support(free), io::MbdynSupport::free_at_first_interface);
  const std::map<std::pair<bool, io::MbdynClamp>, unsigned int> expected_clamps{
    {{true, io::MbdynClamp::automatic}, 1}, {{true, io::MbdynClamp::yes}, 1}, {{true, io::MbdynClamp::no}, 0},
    {{false, io::MbdynClamp::automatic}, 0}, {{false, io::MbdynClamp::yes}, 1}, {{false, io::MbdynClamp::no}, 0}};
  for (const auto &[key, clamps] : expected_clamps)
    {
      const auto &body = key.first ? supported : free;
      const std::string text = io::mbdyn_elm_text(body, "b.fem", key.second);
      const std::string what = std::string(key.first ? "supported" : "free") + " body, clamp " +
                               std::to_string(static_cast<int>(key.second));
      const ElmFile elm = read_elm_strictly(text);
      ASSERT_EQ(elm.modal.size(), 1u) << what;
      ASSERT_EQ(elm.clamps.size(), clamps) << what << ":\n" << text;
      if (clamps)
        {
          EXPECT_EQ(elm.clamps[0].node, elm.modal[0].node) << what;
          EXPECT_NE(elm.clamps[0].label, elm.modal[0].label) << what;
        }
      else
        EXPECT_EQ(text.find("\njoint: flextrack_clamp_joint"), std::string::npos) << what;
      EXPECT_EQ(stated_joint_count(text), static_cast<int>(elm.modal.size() + elm.clamps.size())) << what << ":\n" << text;
      EXPECT_EQ(up_to_the_modal_joint(text), up_to_the_modal_joint(io::mbdyn_elm_text(body, "b.fem"))) << what;
      if (key.second == io::MbdynClamp::automatic) { EXPECT_EQ(text, io::mbdyn_elm_text(body, "b.fem")) << "the default"; }
    }
  EXPECT_NE(io::mbdyn_elm_text(supported, "b.fem", io::MbdynClamp::no).find("--mbdyn-clamp no"), std::string::npos)
    << "the file says why a supported body has no clamp";
  // The files of 'flextrack export': STEM.fem and STEM.elm, the .elm reading STEM.fem.
  const auto files = io::mbdyn_export_files(supported, "pendulum", io::MbdynClamp::no);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0].first, "pendulum.fem");
  EXPECT_EQ(files[0].second, io::mbdyn_fem_text(supported));
  EXPECT_EQ(files[1].first, "pendulum.elm");
  EXPECT_EQ(files[1].second, io::mbdyn_elm_text(supported, "pendulum.fem", io::MbdynClamp::no));
}

TEST(MbdynExport, clamp_option_names_its_allowed_values)
{
  EXPECT_EQ(io::mbdyn_clamp_from_name("auto", "--mbdyn-clamp"), io::MbdynClamp::automatic);
  EXPECT_EQ(io::mbdyn_clamp_from_name("yes", "--mbdyn-clamp"), io::MbdynClamp::yes);
  EXPECT_EQ(io::mbdyn_clamp_from_name("no", "--mbdyn-clamp"), io::MbdynClamp::no);
  for (const std::string bad : {"maybe", "YES", "", "no ", "1"})
    try
      {
        io::mbdyn_clamp_from_name(bad, "--mbdyn-clamp");
        ADD_FAILURE() << "'" << bad << "' accepted";
      }
    catch (const InputError &e)
      {
        EXPECT_EQ(e.entry(), "--mbdyn-clamp");
        EXPECT_NE(std::string(e.what()).find("allowed: auto, yes, no"), std::string::npos) << e.what();
      }
}
