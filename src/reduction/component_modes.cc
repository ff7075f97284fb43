#include <io/input_error.h>
#include <reduction/component_modes.h>
#include <reduction/sparse_factorization.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flextrack::reduction
{
using namespace dealii;

void ReductionSettings::declare_parameters(ParameterHandler &prm)
{
  prm.enter_subsection("Reduction");
  prm.declare_entry("Method", "craig bampton", Patterns::Selection("craig bampton|free interface"),
                    "'craig bampton': fixed-interface normal modes plus interface constraint modes; 'free "
                    "interface': free-interface normal modes plus residual attachment modes (inertia relief "
                    "and a mean-axis body frame for a free body).");
  prm.declare_entry("Number of normal modes", "20", Patterns::Integer(0),
                    "Normal modes in the basis [-] (rigid-body modes of a free body not counted).");
  prm.declare_entry("Track arms", "", Patterns::Anything(),
                    "Arms that carry a sliding contact, separated by commas: each gets track load modes.");
  prm.declare_entry("Track stations", "8", Patterns::Integer(1),
                    "Load stations per track arm [-]: unit forces along x, y and z at s_k = k L / n, k = 1..n.");
  prm.declare_entry("Damping ratio", "0", Patterns::Double(0),
                    "Modal damping ratio zeta of every reduced mode [-]: C = diag(2 zeta w_i).");
  prm.declare_entry("Rayleigh mass coefficient", "0", Patterns::Double(0),
                    "Rayleigh damping alpha [1/s], added to C as alpha M.");
  prm.declare_entry("Rayleigh stiffness coefficient", "0", Patterns::Double(0),
                    "Rayleigh damping beta [s], added to C as beta K.");
  prm.leave_subsection();
}

ReductionSettings ReductionSettings::parse_parameters(ParameterHandler &prm)
{
  ReductionSettings s;
  s.modal = ModalSettings::parse_parameters(prm);
  prm.enter_subsection("Reduction");
  s.method = prm.get("Method") == "free interface" ? Method::free_interface : Method::craig_bampton;
  s.n_normal_modes = prm.get_integer("Number of normal modes");
  std::string list = prm.get("Track arms");
  std::replace(list.begin(), list.end(), ',', ' ');
  std::istringstream in(list);
  for (std::string name; in >> name;) s.track_arms.push_back(name);
  s.n_stations = prm.get_integer("Track stations");
  s.damping_ratio = prm.get_double("Damping ratio");
  s.rayleigh_mass = prm.get_double("Rayleigh mass coefficient");
  s.rayleigh_stiffness = prm.get_double("Rayleigh stiffness coefficient");
  prm.leave_subsection();
  return s;
}

std::string ReductionSettings::method_name() const
{
  return method == Method::craig_bampton ? "craig bampton" : "free interface";
}

std::vector<double> ReducedBasis::frequencies_hz() const
{
  std::vector<double> f;
  for (unsigned int i = 0; i < stiffness.m(); ++i) f.push_back(frequency_hz(stiffness(i, i) / mass(i, i)));
  std::sort(f.begin(), f.end());
  return f;
}

namespace
{
/// K and M restricted to the dofs with keep[i] >= 0 (renumbered keep[i]).
void restrict_matrices(const TrilinosWrappers::SparseMatrix &K, const TrilinosWrappers::SparseMatrix &M,
                       const std::vector<int> &keep, const unsigned int n_kept, TrilinosWrappers::SparseMatrix &K_kept,
                       TrilinosWrappers::SparseMatrix &M_kept)
{
  const Epetra_MpiComm comm(MPI_COMM_SELF);
  const Epetra_Map map(static_cast<int>(n_kept), 0, comm);
  for (int which = 0; which < 2; ++which)
    {
      const Epetra_CrsMatrix &a = (which == 0 ? K : M).trilinos_matrix();
      Epetra_CrsMatrix b(Copy, map, a.MaxNumEntries());
      std::vector<int> cols;
      std::vector<double> vals;
      for (int r = 0; r < a.NumMyRows(); ++r)
        {
          const int row = keep[a.RowMap().GID(r)];
          if (row < 0) continue;
          int n, *idx;
          double *v;
          a.ExtractMyRowView(r, n, v, idx);
          cols.clear();
          vals.clear();
          for (int e = 0; e < n; ++e)
            if (const int c = keep[a.ColMap().GID(idx[e])]; c >= 0)
              {
                cols.push_back(c);
                vals.push_back(v[e]);
              }
          b.InsertGlobalValues(row, cols.size(), vals.data(), cols.data());
        }
      b.FillComplete();
      (which == 0 ? K_kept : M_kept).reinit(b);
    }
}

/// The body's matrices with some dofs clamped: restricted matrices, their factorisation, and
/// the maps between the two numberings.
class ClampedBody
{
public:
  ClampedBody(const fem::BodyModel &body, const std::vector<unsigned int> &clamped)
    : keep(body.n_dofs(), 0), K_ptr(&body.stiffness_matrix()), M_ptr(&body.mass_matrix())
  {
    for (const auto i : clamped) keep[i] = -1;
    for (unsigned int i = 0; i < keep.size(); ++i)
      if (keep[i] >= 0)
        {
          keep[i] = kept.size();
          kept.push_back(i);
        }
    if (!clamped.empty())
      {
        restrict_matrices(body.stiffness_matrix(), body.mass_matrix(), keep, kept.size(), K_kept, M_kept);
        K_ptr = &K_kept;
        M_ptr = &M_kept;
      }
  }
  /// The matrices of the kept dofs (the body's own if nothing is clamped).
  const TrilinosWrappers::SparseMatrix &K() const { return *K_ptr; }
  const TrilinosWrappers::SparseMatrix &M() const { return *M_ptr; }
  unsigned int size() const { return kept.size(); }
  /// x = K_c^{-1} b for a body-dof load b; zero on the clamped dofs. Factorises on first use.
  Vector<double> solve(const Vector<double> &b)
  {
    if (!factorization) factorization = std::make_unique<SparseFactorization>(K(), M(), 0.0, "cholmod");
    Vector<double> bc(kept.size()), xc(kept.size());
    for (unsigned int j = 0; j < kept.size(); ++j) bc[j] = b[kept[j]];
    factorization->solve(bc.begin(), xc.begin());
    return expand(xc);
  }
  Vector<double> expand(const Vector<double> &xc) const
  {
    Vector<double> x(keep.size());
    for (unsigned int j = 0; j < kept.size(); ++j) x[kept[j]] = xc[j];
    return x;
  }
  std::vector<int> keep;
  std::vector<unsigned int> kept;

private:
  TrilinosWrappers::SparseMatrix K_kept, M_kept;
  const TrilinosWrappers::SparseMatrix *K_ptr, *M_ptr;
  std::unique_ptr<SparseFactorization> factorization;
};

/// M-orthonormal Gram-Schmidt: appends v (made M-orthogonal to @p against and to @p basis) to
/// @p basis unless it is dependent; returns whether it was kept.
bool append_orthonormal(Vector<double> v, const std::vector<Vector<double>> &against,
                        std::vector<Vector<double>> &basis, const TrilinosWrappers::SparseMatrix &M)
{
  Vector<double> Mv(v.size());
  M.vmult(Mv, v);
  const double original = std::sqrt(v * Mv);
  if (!(original > 0)) return false;
  for (int pass = 0; pass < 2; ++pass) // twice is enough (Kahan)
    {
      M.vmult(Mv, v);
      for (const auto *set : std::array<const std::vector<Vector<double>> *, 2>{{&against, &basis}})
        for (const auto &phi : *set) v.add(-(phi * Mv), phi);
    }
  M.vmult(Mv, v);
  const double norm = std::sqrt(v * Mv);
  if (!(norm > 1e-8 * original)) return false;
  v /= norm;
  basis.push_back(std::move(v));
  return true;
}

/// Rigid-body modes, M-orthonormal.
std::vector<Vector<double>> orthonormal_rigid_modes(const fem::BodyModel &body)
{
  std::vector<Vector<double>> R;
  const std::vector<Vector<double>> none;
  for (auto &r : body.rigid_body_modes()) append_orthonormal(r, none, R, body.mass_matrix());
  AssertThrow(R.size() == 6, ExcMessage("the body's rigid-body modes are dependent (all nodes on one line?)"));
  return R;
}

/// f - M R R^T f: a load balanced by the rigid-body inertia forces it causes.
Vector<double> inertia_relief(const Vector<double> &f, const std::vector<Vector<double>> &R,
                              const TrilinosWrappers::SparseMatrix &M)
{
  Vector<double> g = f, MR(f.size());
  for (const auto &r : R)
    {
      M.vmult(MR, r);
      g.add(-(r * f), MR);
    }
  return g;
}
} // namespace

ReducedBasis reduce(const fem::BodyModel &body, const ReductionSettings &settings)
{
  const bool free_body = !body.is_supported();
  const bool craig_bampton = settings.method == ReductionSettings::Method::craig_bampton;
  const auto &interfaces = body.interfaces();
  if (free_body && interfaces.empty() && (craig_bampton || !settings.track_arms.empty()))
    throw InputError("Body/Interfaces", std::string("a free body reduced by ") +
                                          (craig_bampton ? "Craig-Bampton" : "free-interface modes with track load modes") +
                                          " needs an interface: the first interface is the body frame (the static "
                                          "solves are anchored there); add one, or support the body");
  std::vector<unsigned int> track_arms;
  for (const auto &name : settings.track_arms)
    {
      unsigned int a = 0;
      while (a < body.n_arms() && body.arm_name(a) != name) ++a;
      if (a == body.n_arms())
        throw InputError("Reduction/Track arms", "'" + name + "' is not an arm of the body (listed in Body/Arms)");
      track_arms.push_back(a);
    }

  // Clamped dofs: all interfaces (Craig-Bampton) or, for static solves of a free body, the
  // frame interface.
  std::vector<unsigned int> clamped;
  if (craig_bampton)
    for (const auto &p : interfaces) clamped.insert(clamped.end(), p.dofs.begin(), p.dofs.end());
  else if (free_body && !interfaces.empty())
    clamped.assign(interfaces[0].dofs.begin(), interfaces[0].dofs.end());
  ClampedBody anchored(body, clamped);

  const TrilinosWrappers::SparseMatrix &M = body.mass_matrix();
  // Mean-axis frame (free-interface method, free body): every vector M-orthogonal to R.
  const unsigned int n_rigid = (!craig_bampton && free_body) ? 6 : 0;
  const std::vector<Vector<double>> R = n_rigid ? orthonormal_rigid_modes(body) : std::vector<Vector<double>>();
  const unsigned int n_free = craig_bampton ? anchored.size() : body.n_dofs();
  if (settings.n_normal_modes + n_rigid >= n_free)
    {
      std::ostringstream m;
      m << settings.n_normal_modes << " normal modes requested, but the body has only " << n_free
        << " free degrees of freedom" << (n_rigid ? " (6 of them rigid-body motions)" : "")
        << "; allowed: fewer than " << n_free - n_rigid << ", or refine the mesh";
      throw InputError("Reduction/Number of normal modes", m.str());
    }

  ReducedBasis r;
  std::vector<Vector<double>> basis;
  std::vector<double> eigenvalues; // of the normal modes, for the residual flexibility
  if (settings.n_normal_modes > 0)
    {
      ModalSettings modal = settings.modal;
      modal.n_modes = settings.n_normal_modes + n_rigid;
      const TrilinosWrappers::SparseMatrix &K_eig = craig_bampton ? anchored.K() : body.stiffness_matrix();
      const TrilinosWrappers::SparseMatrix &M_eig = craig_bampton ? anchored.M() : M;
      const double shift = std::isnan(modal.shift) ? automatic_shift(K_eig, M_eig) : modal.shift;
      const Modes modes = lowest_modes(K_eig, M_eig, n_free, modal, shift,
                                       modal.direct_solver == "auto" ? "cholmod" : modal.direct_solver);
      if (n_rigid == 0 && modes.eigenvalues[0] < 1e-10 * std::abs(modes.eigenvalues.back()))
        throw SolverError("the " + std::string(free_body ? "body, held at its first interface," : "supported body") +
                          " still has a zero-energy mode (eigenvalue " + std::to_string(modes.eigenvalues[0]) +
                          " rad^2/s^2): a mechanism; check Body/Ties (a region that cannot carry the arm root's "
                          "rotation) and the supports");
      if (n_rigid > 0)
        {
          // The six near-zero modes are the rigid-body motions (replaced by the exact R); a
          // seventh near-zero eigenvalue means a part that is not connected.
          const double largest = std::abs(modes.eigenvalues.back());
          if (std::abs(modes.eigenvalues[6]) < 1e-8 * largest)
            throw SolverError("the free body has more than six zero-energy modes (eigenvalue " +
                              std::to_string(modes.eigenvalues[6]) + " rad^2/s^2): a part is not tied to the rest; "
                              "check Body/Ties");
        }
      for (unsigned int i = n_rigid; i < modes.shapes.size(); ++i)
        {
          Vector<double> phi = craig_bampton ? anchored.expand(modes.shapes[i]) : modes.shapes[i];
          if (append_orthonormal(phi, R, basis, M)) eigenvalues.push_back(modes.eigenvalues[i]);
        }
      r.n_normal = basis.size();
    }

  // Static vectors: constraint modes (Craig-Bampton) or residual attachment modes.
  auto static_response = [&](const Vector<double> &f) {
    return n_rigid ? anchored.solve(inertia_relief(f, R, M)) : anchored.solve(f);
  };
  const auto &K = body.stiffness_matrix();
  for (unsigned int p = 0; p < interfaces.size(); ++p)
    {
      if (craig_bampton && free_body && p == 0) continue; // the body frame
      for (const auto dof : interfaces[p].dofs)
        {
          Vector<double> v(body.n_dofs());
          if (craig_bampton)
            {
              // u = e_j on the interface, K_oo u_o = -K_oj elsewhere.
              Vector<double> e(body.n_dofs()), Ke(body.n_dofs());
              e[dof] = 1;
              K.vmult(Ke, e);
              Ke *= -1;
              for (const auto c : clamped) Ke[c] = 0;
              v = anchored.solve(Ke);
              v[dof] = 1;
            }
          else
            {
              Vector<double> f(body.n_dofs());
              f[dof] = 1;
              v = static_response(f);
            }
          if (append_orthonormal(v, R, basis, M))
            ++r.n_interface;
          else
            ++r.n_dropped;
        }
    }
  for (const auto a : track_arms)
    {
      const double L = body.arm_model(a).arm().curve->length();
      for (unsigned int k = 1; k <= settings.n_stations; ++k)
        for (unsigned int d = 0; d < 3; ++d)
          {
            const Vector<double> f = body.arm_point_load(a, k * L / settings.n_stations, Tensor<1, 3>(Point<3>::unit_vector(d)));
            if (append_orthonormal(static_response(f), R, basis, M))
              ++r.n_track;
            else
              ++r.n_dropped;
          }
    }
  if (basis.empty()) throw InputError("Reduction/Number of normal modes", "the basis is empty: ask for normal modes, interfaces or track arms");

  // Rotate the basis onto the reduced eigenvectors: Phi^T M Phi = 1, Phi^T K Phi = diag(w^2).
  const unsigned int n = basis.size();
  std::vector<Vector<double>> Kphi(n, Vector<double>(body.n_dofs())), Mphi(n, Vector<double>(body.n_dofs()));
  LAPACKFullMatrix<double> Kr(n), Mr(n);
  for (unsigned int b = 0; b < n; ++b)
    {
      K.vmult(Kphi[b], basis[b]);
      M.vmult(Mphi[b], basis[b]);
    }
  for (unsigned int a = 0; a < n; ++a)
    for (unsigned int b = 0; b < n; ++b)
      {
        Kr(a, b) = 0.5 * (basis[a] * Kphi[b] + basis[b] * Kphi[a]);
        Mr(a, b) = 0.5 * (basis[a] * Mphi[b] + basis[b] * Mphi[a]);
      }
  std::vector<Vector<double>> V(n, Vector<double>(n));
  Kr.compute_generalized_eigenvalues_symmetric(Mr, V);
  std::vector<unsigned int> order(n);
  for (unsigned int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](unsigned int i, unsigned int j) { return Kr.eigenvalue(i).real() < Kr.eigenvalue(j).real(); });
  r.modes.assign(n, Vector<double>(body.n_dofs()));
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int b = 0; b < n; ++b) r.modes[i].add(V[order[i]][b], basis[b]);

  // The reduced matrices of the final basis, as they are (not assumed diagonal).
  r.stiffness.reinit(n, n);
  r.mass.reinit(n, n);
  for (unsigned int b = 0; b < n; ++b)
    {
      K.vmult(Kphi[b], r.modes[b]);
      M.vmult(Mphi[b], r.modes[b]);
    }
  for (unsigned int a = 0; a < n; ++a)
    for (unsigned int b = 0; b < n; ++b)
      {
        r.stiffness(a, b) = 0.5 * (r.modes[a] * Kphi[b] + r.modes[b] * Kphi[a]);
        r.mass(a, b) = 0.5 * (r.modes[a] * Mphi[b] + r.modes[b] * Mphi[a]);
      }
  r.damping.reinit(n, n);
  for (unsigned int a = 0; a < n; ++a)
    for (unsigned int b = 0; b < n; ++b)
      r.damping(a, b) = settings.rayleigh_mass * r.mass(a, b) + settings.rayleigh_stiffness * r.stiffness(a, b);
  for (unsigned int a = 0; a < n; ++a)
    r.damping(a, a) += 2 * settings.damping_ratio * std::sqrt(std::max(0.0, r.stiffness(a, a) / r.mass(a, a))) * r.mass(a, a);
  return r;
}
} // namespace flextrack::reduction
