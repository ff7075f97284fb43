#include <base/input_error.h>
#include <base/names.h>
#include <io/mbdyn_export.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace flextrack::io
{
using namespace dealii;

namespace
{
/// Numbers, at most 6 a line, each with 17 significant digits and a plain 'e' exponent.
class NumberWriter
{
public:
  explicit NumberWriter(std::ostringstream &out) : out(out) {}
  void add(const double v)
  {
    char text[32];
    std::snprintf(text, sizeof(text), "%.16e", v == 0 ? 0.0 : v); // no "-0"
    out << (count % 6 ? " " : "") << text;
    if (++count % 6 == 0) out << "\n";
  }
  /// Ends the current line (if one is open) and restarts the count.
  void end_line()
  {
    if (count % 6) out << "\n";
    count = 0;
  }

private:
  std::ostringstream &out;
  unsigned int count = 0;
};

/// The shortest text that reads back as the same double (for positions in the .elm comments).
std::string shortest(const double v)
{
  char text[32];
  const auto r = std::to_chars(text, text + sizeof(text), v == 0 ? 0.0 : v);
  return std::string(text, r.ptr);
}

/// (A + A^T) / 2, each pair computed once: the result is symmetric bit for bit.
dealii::FullMatrix<double> symmetric_part(const dealii::FullMatrix<double> &A)
{
  dealii::FullMatrix<double> S(A.m(), A.n());
  for (unsigned int i = 0; i < A.m(); ++i)
    {
      S(i, i) = A(i, i);
      for (unsigned int j = 0; j < i; ++j) S(i, j) = S(j, i) = 0.5 * (A(i, j) + A(j, i));
    }
  return S;
}

/// Off-diagonal terms at most mbdyn_round_off_threshold sqrt(|S_ii S_jj|) set to 0.
void drop_round_off(dealii::FullMatrix<double> &S)
{
  for (unsigned int i = 0; i < S.m(); ++i)
    for (unsigned int j = 0; j < i; ++j)
      if (std::abs(S(i, j)) <= mbdyn_round_off_threshold * std::sqrt(std::abs(S(i, i) * S(j, j)))) S(i, j) = S(j, i) = 0;
}

/// The end of the .elm: how the modal node is held (a clamp, or a comment saying how to hold it),
/// for a body with @p support exported with @p choice; @p first labels the first interface.
std::string holding_text(const MbdynSupport support, const MbdynClamp choice, const std::string &first)
{
  std::ostringstream out;
  const std::string clamp = "joint: flextrack_clamp_joint, clamp, flextrack_modal_node, node, node;";
  const std::string clamp_label = "set: ifndef integer flextrack_clamp_joint = 1001;";
  if (choice == MbdynClamp::no && support == MbdynSupport::supported)
    {
      out << "# The body has supports, fixed in the body frame (its modes are those of the supported body).\n"
          << "# Exported with '--mbdyn-clamp no': the modal node is not clamped here, so the including model\n"
          << "# must hold it by its own joint at the supports (e.g. a revolute pin at a point of a supported\n"
          << "# face, offset from the modal node in the body frame); count 1 joint for this file in the\n"
          << "# control data.\n";
      return out.str();
    }
  if (choice == MbdynClamp::yes && support != MbdynSupport::supported)
    {
      out << "# Clamped as asked ('--mbdyn-clamp yes'; the data show no supports): the modal node is held\n"
          << "# where it stands; count 2 joints for this file in the control data.\n"
          << clamp_label << "\n" << clamp << "\n";
      return out.str();
    }
  switch (support)
    {
      case MbdynSupport::supported:
        out << "# The body has supports, fixed in the body frame (its modes are those of the supported body),\n"
            << "# so the modal node must be held: clamped where it stands; count 2 joints for this file in the\n"
            << "# control data. For supports on a moving part, replace the clamp by a joint to that part\n"
            << "# (or export with '--mbdyn-clamp no').\n"
            << clamp_label << "\n"
            << clamp << "\n";
        break;
      case MbdynSupport::free_at_first_interface:
        out << "# A free body: every mode is 0 at its first interface '" << first << "' (its body frame), so\n"
            << "# the modal node moves freely; count 1 joint for this file in the control data. Only if the\n"
            << "# body's scene has supports (all at '" << first << "'), hold the modal node, e.g.\n"
            << "# " << clamp_label << "\n# " << clamp << "\n";
        break;
      case MbdynSupport::free_mean_axes:
        out << "# A free body (mean axes: I3 = I4 = 0), so the modal node moves freely; count 1 joint for\n"
            << "# this file in the control data.\n";
        break;
      case MbdynSupport::no_modes:
        out << "# No modes: a rigid body. Count 1 joint for this file in the control data; if the body's\n"
            << "# scene has supports, hold the modal node, e.g.\n"
            << "# " << clamp_label << "\n# " << clamp << "\n";
        break;
    }
  return out.str();
}
} // namespace

MbdynMatrices mbdyn_matrices(const reduction::ReducedBody &body)
{
  MbdynMatrices r{symmetric_part(body.mass), symmetric_part(body.stiffness), symmetric_part(body.damping), true};
  for (unsigned int i = 0; i < r.mass.m(); ++i)
    for (unsigned int j = 0; j < r.mass.n(); ++j)
      if (!(std::abs(r.mass(i, j) - (i == j ? 1.0 : 0.0)) <= mbdyn_orthonormal_tolerance)) r.mass_orthonormal = false;
  if (r.mass_orthonormal)
    for (auto *A : {&r.mass, &r.stiffness, &r.damping}) drop_round_off(*A);
  return r;
}

MbdynSupport mbdyn_support(const reduction::ReducedBody &body)
{
  const unsigned int n = body.n_modes();
  if (n == 0) return MbdynSupport::no_modes;
  if (!body.interfaces.empty())
    {
      bool all_zero = true;
      for (unsigned int c = 0; c < 6; ++c)
        for (unsigned int k = 0; k < n; ++k) all_zero = all_zero && body.interfaces[0].modes(c, k) == 0;
      if (all_zero) return MbdynSupport::free_at_first_interface;
    }
  // Mean axes: |I3(a, k)| <= sqrt(m M_kk) and |I4(a, k)| <= sqrt(J_O(a, a) M_kk) (Cauchy-Schwarz
  // in the mass inner product); a free-interface basis of a free body is M-orthogonal to the rigid
  // motions, so both vanish to round-off, relative 1e-8 of these bounds.
  const auto &inv = body.invariants;
  bool mean_axes = inv.I3.m() == 3 && inv.I4.m() == 3 && inv.I3.n() == n && inv.I4.n() == n;
  for (unsigned int a = 0; a < 3 && mean_axes; ++a)
    for (unsigned int k = 0; k < n; ++k)
      {
        const double Mkk = std::abs(body.mass(k, k));
        mean_axes = mean_axes && std::abs(inv.I3(a, k)) <= 1e-8 * std::sqrt(std::abs(inv.mass) * Mkk) &&
                    std::abs(inv.I4(a, k)) <= 1e-8 * std::sqrt(std::abs(inv.inertia_origin[a][a]) * Mkk);
      }
  return mean_axes ? MbdynSupport::free_mean_axes : MbdynSupport::supported;
}

std::string mbdyn_node_label(const std::string &name)
{
  // Names read from a file or a scene already follow base::name_rule(); anything else (a body
  // built in code) is mapped into that set, so a label can never end a quoted MBDyn string.
  std::string label = name.substr(0, base::max_name_length);
  for (auto &c : label)
    if (!base::is_valid_name(std::string(1, c))) c = '_';
  return label.empty() ? "_" : label;
}

std::string mbdyn_fem_text(const reduction::ReducedBody &body)
{
  const auto &inv = body.invariants;
  // Exposed nodes: the interfaces, then the output points.
  std::vector<const reduction::ReducedBody::Interface *> exposed;
  for (const auto &p : body.interfaces) exposed.push_back(&p);
  for (const auto &p : body.output_points) exposed.push_back(&p);
  const unsigned int n = body.n_modes(), N = exposed.size();
  const Tensor<2, 3> J = inv.inertia_about_centre_of_mass();
  {
    LAPACKFullMatrix<double> A(3, 3);
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j) A(i, j) = 0.5 * (J[i][j] + J[j][i]);
    A.compute_eigenvalues();
    double smallest = 1e300;
    for (unsigned int i = 0; i < 3; ++i) smallest = std::min(smallest, A.eigenvalue(i).real());
    if (!(inv.mass > 0) || !(smallest > 1e-12 * trace(J)))
      throw InputError("", "cannot export to MBDyn: the inertia tensor about the centre of mass is not positive "
                           "definite (smallest principal inertia " + std::to_string(smallest) +
                           " kg m^2), which MBDyn cannot integrate; is all the mass on one line?");
  }

  std::ostringstream out;
  NumberWriter num(out);
  // The one comment line that follows the RG 1 marker carries the provenance.
  out << "** RECORD GROUP 1, HEADER\n";
  out << "**   REVISION, NODES, MODES, 0, 0, 0 - FlexTrack " FLEXTRACK_VERSION ", " << base::printable_excerpt(body.method, 80)
      << ", SI units, input hash " << base::printable_excerpt(body.input_hash, 80) << "\n";
  out << "REV0 " << N << " " << n << " 0 0 0\n";
  out << "** RECORD GROUP 2, FINITE ELEMENT NODE LIST\n";
  for (unsigned int i = 0; i < N; ++i) out << (i ? " " : "") << mbdyn_node_label(exposed[i]->name);
  if (N) out << "\n";
  for (unsigned int d = 0; d < 3; ++d)
    {
      out << "** RECORD GROUP " << 5 + d << ", FINITE ELEMENT NODE " << "XYZ"[d] << "\n";
      for (const auto *p : exposed) num.add(p->position[d]);
      num.end_line();
    }
  out << "** RECORD GROUP 8, MODE SHAPES\n";
  for (unsigned int k = 0; k < n; ++k)
    {
      out << "**    NORMAL MODE SHAPE # " << k + 1 << "\n";
      for (const auto *p : exposed)
        {
          for (unsigned int c = 0; c < 6; ++c) num.add(p->modes(c, k));
          num.end_line();
        }
    }
  auto matrix = [&](const int group, const char *title, const FullMatrix<double> &A) {
    out << "** RECORD GROUP " << group << ", " << title << "\n";
    for (unsigned int i = 0; i < A.m(); ++i)
      {
        for (unsigned int j = 0; j < A.n(); ++j) num.add(A(i, j));
        num.end_line();
      }
  };
  const MbdynMatrices written = mbdyn_matrices(body);
  matrix(9, "MODAL MASS MATRIX", written.mass);
  matrix(10, "MODAL STIFFNESS MATRIX", written.stiffness);
  out << "** RECORD GROUP 12, RIGID BODY MASS, CENTRE OF MASS, INERTIA ABOUT THE CENTRE OF MASS\n";
  num.add(inv.mass);
  num.end_line();
  const Point<3> c = inv.centre_of_mass();
  for (unsigned int d = 0; d < 3; ++d) num.add(c[d]);
  num.end_line();
  for (unsigned int i = 0; i < 3; ++i)
    {
      for (unsigned int j = 0; j < 3; ++j) num.add(J[i][j]);
      num.end_line();
    }
  matrix(13, "MODAL DAMPING MATRIX", written.damping);
  matrix(14, "INVARIANT 3", inv.I3);
  matrix(15, "INVARIANT 4", inv.I4);
  // I8_j = -int rho x~ phi_j~ = tr(P_j) 1 - P_j; rows r, then mode j, then column c.
  out << "** RECORD GROUP 16, INVARIANT 8\n";
  for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int col = 0; col < 3; ++col) num.add((r == col ? trace(inv.P[j]) : 0.0) - inv.P[j][r][col]);
      num.end_line();
    }
  // I5_jk = int rho phi_j x phi_k; rows r, then j, then k.
  out << "** RECORD GROUP 17, INVARIANT 5\n";
  for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int k = 0; k < n; ++k) num.add(inv.I5(j, k)[r]);
      num.end_line();
    }
  // I9_jk = int rho phi_j~ phi_k~ = Q_kj - tr(Q_jk) 1; rows r, then j, then k, then column c.
  out << "** RECORD GROUP 18, INVARIANT 9\n";
  for (unsigned int r = 0; r < 3; ++r)
    {
      for (unsigned int j = 0; j < n; ++j)
        for (unsigned int k = 0; k < n; ++k)
          for (unsigned int col = 0; col < 3; ++col)
            num.add(inv.Q[k * n + j][r][col] - (r == col ? trace(inv.Q[j * n + k]) : 0.0));
      num.end_line();
    }
  out << "** END OF FILE\n";
  return out.str();
}

std::string mbdyn_clamp_names() { return "auto, yes, no"; }

MbdynClamp mbdyn_clamp_from_name(const std::string &name, const std::string &entry)
{
  if (name == "auto") return MbdynClamp::automatic;
  if (name == "yes") return MbdynClamp::yes;
  if (name == "no") return MbdynClamp::no;
  throw InputError(entry, "unknown value '" + base::printable_excerpt(name) + "' for the clamp of the MBDyn modal node; allowed: " +
                            mbdyn_clamp_names());
}

std::vector<std::pair<std::string, std::string>> mbdyn_export_files(const reduction::ReducedBody &body,
                                                                    const std::string &stem, const MbdynClamp clamp)
{
  return {{stem + ".fem", mbdyn_fem_text(body)}, {stem + ".elm", mbdyn_elm_text(body, stem + ".fem", clamp)}};
}

std::string mbdyn_elm_text(const reduction::ReducedBody &body, const std::string &fem_file_name, const MbdynClamp clamp_choice)
{
  if (fem_file_name.empty() || fem_file_name.find_first_of("\"\\") != std::string::npos ||
      base::printable_excerpt(fem_file_name, fem_file_name.size()) != fem_file_name)
    throw InputError("", "cannot name the .fem file '" + base::printable_excerpt(fem_file_name) +
                           "' in an MBDyn string (no quotes, backslashes or control characters)");
  const unsigned int n = body.n_modes(), N = body.interfaces.size();
  const MbdynSupport support = mbdyn_support(body);
  const std::string first = N ? mbdyn_node_label(body.interfaces[0].name) : "";
  std::ostringstream out;
  out << "# MBDyn include file for the elements block, written by FlexTrack for the reduced body of\n# "
      << base::printable_excerpt(body.source, 200) << " (" << n << " modes, " << base::printable_excerpt(body.method, 80)
      << ", SI units). The labels are set only if not\n"
      << "# set before ('ifndef'). In the nodes block: the modal node at the body-frame origin with the\n"
      << "# body-frame axes (a body at rest in the global frame: modal, null, eye, null, null), and per\n"
      << "# interface a structural node at the position below, oriented as the modal node, moving with\n"
      << "# the modal node's rigid motion. Do not move the modal node with 'origin node': MBDyn would\n"
      << "# shift the node positions and record group 12 but not the invariants 14-18.\n";
  out << "set: ifndef integer flextrack_modal_joint = 1000;\n";
  out << "set: ifndef integer flextrack_modal_node = 1000;\n";
  for (unsigned int i = 0; i < N; ++i)
    {
      const auto &p = body.interfaces[i];
      out << "set: ifndef integer flextrack_node_" << mbdyn_node_label(p.name) << " = " << 1001 + i << ";  # at ("
          << shortest(p.position[0]) << ", " << shortest(p.position[1]) << ", " << shortest(p.position[2]) << ") m\n";
    }
  // The modal joint in the manual's order: node, mode count, FEM node count ('from file'),
  // damping, file name, interface count, interfaces.
  out << "joint: flextrack_modal_joint, modal,\n"
      << "\tflextrack_modal_node,\n"
      << "\t" << n << ",  # modes\n"
      << "\tfrom file,  # FEM nodes: those of the .fem file\n"
      << "\tdamping from file,  # record group 13\n"
      << "\t\"" << fem_file_name << "\",\n"
      << "\t" << N << (N ? "," : ";") << "  # interface nodes\n";
  for (unsigned int i = 0; i < N; ++i)
    {
      const std::string label = mbdyn_node_label(body.interfaces[i].name);
      out << "\t\t\"" << label << "\", flextrack_node_" << label << ", null" << (i + 1 == N ? ";" : ",") << "\n";
    }
  out << holding_text(support, clamp_choice, first);
  return out.str();
}
} // namespace flextrack::io
