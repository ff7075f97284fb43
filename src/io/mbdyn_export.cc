#include <base/input_error.h>
#include <base/names.h>
#include <io/mbdyn_export.h>

#include <deal.II/lac/lapack_full_matrix.h>

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
} // namespace

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
  matrix(9, "MODAL MASS MATRIX", body.mass);
  matrix(10, "MODAL STIFFNESS MATRIX", body.stiffness);
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
  matrix(13, "MODAL DAMPING MATRIX", body.damping);
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

std::string mbdyn_elm_text(const reduction::ReducedBody &body, const std::string &fem_file_name)
{
  std::ostringstream out;
  out << "# MBDyn include file written by FlexTrack " FLEXTRACK_VERSION " for the reduced body of "
      << base::printable_excerpt(body.source, 200) << "\n# (" << body.n_modes() << " modes, "
      << base::printable_excerpt(body.method, 80) << ", SI units). Include it in the elements block\n"
      << "# after setting the labels below: the modal node (a 'structural: ..., modal, ...' node at the\n"
      << "# body frame origin, axes as the body frame) and one multibody node per interface, placed at\n"
      << "# the interface with initial velocities consistent with the modal node's rigid motion.\n";
  out << "set: integer flextrack_modal_joint = 1000;\n";
  out << "set: integer flextrack_modal_node = 1000;\n";
  for (unsigned int i = 0; i < body.interfaces.size(); ++i)
    {
      const auto &p = body.interfaces[i];
      out << "set: integer flextrack_node_" << mbdyn_node_label(p.name) << " = " << 1001 + i << ";  # at ("
          << p.position[0] << ", " << p.position[1] << ", " << p.position[2] << ") m\n";
    }
  out << "joint: flextrack_modal_joint, modal,\n"
      << "\tflextrack_modal_node,\n"
      << "\t" << body.n_modes() << ",  # modes\n"
      << "\tdamping from file,\n"
      << "\t\"" << fem_file_name << "\",\n"
      << "\t" << body.interfaces.size() << (body.interfaces.empty() ? ";" : ",") << "  # interface nodes\n";
  for (unsigned int i = 0; i < body.interfaces.size(); ++i)
    {
      const std::string label = mbdyn_node_label(body.interfaces[i].name);
      out << "\t\t\"" << label << "\", flextrack_node_" << label << ", null"
          << (i + 1 == body.interfaces.size() ? ";" : ",") << "\n";
    }
  return out.str();
}
} // namespace flextrack::io
