#include <base/mpi_session.h>
#include <base/text.h>
#include <base/input_error.h>
#include <reduction/component_modes.h>
#include <base/memory.h>
#include <reduction/sparse_factorization.h>
#include <fem/csr_matrix.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_Map.h>
#include <Epetra_MpiComm.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace flextrack::reduction
{
using namespace dealii;

void ReductionSettings::declare_parameters(ParameterHandler &prm)
{
  prm.enter_subsection("Reduction");
  std::string names, documentation;
  for (const auto &row : reduction_methods())
    {
      names += (names.empty() ? "" : "|") + row.name;
      documentation += (documentation.empty() ? "" : "; ") + ("'" + row.name + "': " + row.description);
    }
  prm.declare_entry("Method", reduction_methods()[0].name, Patterns::Selection(names), documentation + ".");
  prm.declare_entry("Number of normal modes", "20", Patterns::Integer(0),
                    "Normal modes in the basis [-], 0 to 10000 (rigid-body modes of a free body not counted).");
  prm.declare_entry("Track arms", "", Patterns::Anything(),
                    "Arms that carry a sliding contact, separated by commas: each gets track load modes.");
  prm.declare_entry("Track stations", "8", Patterns::Integer(1),
                    "Load stations per track arm [-], 1 to 1000: unit forces along x, y and z at s_k = k L / n, "
                    "k = 1..n (3 static solves and 3 basis vectors per station).");
  prm.declare_entry("Check modes", "0", Patterns::Integer(0),
                    "After reducing, also solve the full FE model for this many lowest frequencies and report "
                    "the largest relative difference and both run times [-], 0 to 10000; 0 = no check.");
  prm.declare_entry("Geometric stiffness", "false", Patterns::Bool(),
                    "Also compute the geometric stiffness of inertial loads (12 unit cases: centrifugal, "
                    "frame acceleration, angular acceleration), so that fast rotating arms stiffen: the axial "
                    "force of each case's static solution times the arms' slope terms, projected on the modes.");
  prm.declare_entry("Damping ratio", "0", Patterns::Double(0),
                    "Modal damping ratio zeta of every reduced mode [-], 0 to 1 (1 = critical damping): "
                    "C = diag(2 zeta w_i).");
  prm.declare_entry("Rayleigh mass coefficient", "0", Patterns::Double(0),
                    "Rayleigh damping alpha [1/s], 0 to 1e4, added to C as alpha M.");
  prm.declare_entry("Rayleigh stiffness coefficient", "0", Patterns::Double(0),
                    "Rayleigh damping beta [s], 0 to 1, added to C as beta K.");
  prm.leave_subsection();
}

ReductionSettings ReductionSettings::parse_parameters(ParameterHandler &prm)
{
  // Counts are bounded before anything is allocated for them: every track station costs three
  // static solves and three basis vectors of the body's size. The damping ranges are
  // judgements: beyond them a value is a unit mistake (zeta = 1 is critical damping; alpha =
  // 1e4 1/s or beta = 1 s damp every mode of an ordinary structure far beyond critical).
  ReductionSettings s;
  s.modal = ModalSettings::parse_parameters(prm);
  const std::string path = "Reduction/";
  prm.enter_subsection("Reduction");
  const std::string method = prm.get("Method");
  for (const auto &row : reduction_methods())
    if (row.name == method) s.method = row.method;
  auto count = [&](const std::string &name, const long lower, const long upper, const std::string &why) {
    const long n = prm.get_integer(name);
    if (n < lower || n > upper)
      throw InputError(path + name, std::to_string(n) + " " + why + "; allowed: " + std::to_string(lower) + " to " +
                                      std::to_string(upper));
    return static_cast<unsigned int>(n);
  };
  s.n_normal_modes = count("Number of normal modes", 0, 10000, "normal modes");
  s.track_arms = base::words(prm.get("Track arms"));
  s.n_stations = count("Track stations", 1, 1000,
                       "stations per track arm (three static solves and three basis vectors of the body's size each)");
  s.n_check_modes = count("Check modes", 0, 10000, "check modes");
  s.geometric_stiffness = prm.get_bool("Geometric stiffness");
  s.damping_ratio = geometry::get_number(prm, "Damping ratio", path, {0, 1, true, "-"});
  s.rayleigh_mass = geometry::get_number(prm, "Rayleigh mass coefficient", path, {0, 1e4, true, "1/s"});
  s.rayleigh_stiffness = geometry::get_number(prm, "Rayleigh stiffness coefficient", path, {0, 1, true, "s"});
  prm.leave_subsection();
  return s;
}

std::string ReductionSettings::method_name() const
{
  return reduction_method(method).name;
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
/// The rows first_row ... first_row + n_rows - 1 of K and M restricted to the dofs with
/// keep[i] >= 0 (renumbered keep[i]), as rows of matrices of @p n_kept rows distributed over
/// @p communicator (all of them on one process).
void restrict_matrices(const TrilinosWrappers::SparseMatrix &K, const TrilinosWrappers::SparseMatrix &M,
                       const std::vector<int> &keep, const unsigned int n_kept, const unsigned int first_row,
                       const unsigned int n_rows, const MPI_Comm communicator, TrilinosWrappers::SparseMatrix &K_kept,
                       TrilinosWrappers::SparseMatrix &M_kept)
{
  // Visit the kept entries of the wanted rows of @p a.
  auto visit = [&](const TrilinosWrappers::SparseMatrix &matrix, auto &&use) {
    const Epetra_CrsMatrix &a = matrix.trilinos_matrix();
    for (int r = 0; r < a.NumMyRows(); ++r)
      {
        const int row = keep[a.RowMap().GID(r)] - static_cast<int>(first_row);
        if (row < 0 || row >= static_cast<int>(n_rows)) continue;
        int n, *idx;
        double *v;
        a.ExtractMyRowView(r, n, v, idx);
        for (int e = 0; e < n; ++e)
          if (const int c = keep[a.ColMap().GID(idx[e])]; c >= 0) use(row, c, v[e]);
      }
  };
  // K: its pattern, then its values.
  std::vector<std::vector<int>> rows(n_rows);
  visit(K, [&](int row, int c, double) { rows[row].push_back(c); });
  fem::CsrMatrix b(std::move(rows));
  visit(K, [&](int row, int c, double v) { b.add(row, c, v); });
  b.to_trilinos(K_kept, first_row, n_kept, communicator);
  // M has K's pattern (one sparsity pattern for the body): K's storage takes its values, and
  // K_kept's graph holds them.
  std::fill(b.values.begin(), b.values.end(), 0.0);
  visit(M, [&](int row, int c, double v) { b.add(row, c, v); });
  b.to_trilinos_on_graph_of(K_kept, M_kept, first_row);
}

/// The body's matrices with some dofs clamped: restricted matrices, their factorisation, and
/// the maps between the two numberings.
///
/// A distributed body (fem/body_model.h) gives distributed restricted matrices: each process
/// keeps the kept dofs of its own block of rows, MUMPS factorises them in parallel (its factor,
/// the memory that limits the size of a body, spread over the processes), the eigen solve runs
/// on PARPACK, and the solutions are gathered so that every process continues with the same
/// whole vectors.
class ClampedBody
{
public:
  ClampedBody(const fem::BodyModel &body, const std::vector<unsigned int> &clamped)
    : keep(body.n_dofs(), 0), communicator(body.communicator()), K_ptr(&body.stiffness_matrix()),
      M_ptr(&body.mass_matrix())
  {
    for (const auto i : clamped) keep[i] = -1;
    for (unsigned int i = 0; i < keep.size(); ++i)
      if (keep[i] >= 0)
        {
          keep[i] = kept.size();
          kept.push_back(i);
        }
    const unsigned int n = kept.size();
    // The kept dofs of this process' rows of the body: a block too, as keep[] keeps the order.
    const unsigned int begin = body.first_owned_row(), end = begin + body.n_owned_rows();
    first_row = std::lower_bound(kept.begin(), kept.end(), begin) - kept.begin();
    n_rows = (std::lower_bound(kept.begin(), kept.end(), end) - kept.begin()) - first_row;
    several = body.distributed();
    // PARPACK needs rows on every process. A body too small for its processes (a
    // block of rows all clamped, a part of the solid without free dofs) is refused on all of
    // them alike, before any of them starts.
    if (several && Utilities::MPI::min(n_rows, communicator) == 0)
      throw SolverError("the body is too small for " + std::to_string(Utilities::MPI::n_mpi_processes(communicator)) +
                        " processes: one of them holds none of its free degrees of freedom (" + std::to_string(n) +
                        " in all); reduce it with fewer processes (mpirun -np) or serially");
    if (!clamped.empty())
      {
        restrict_matrices(body.stiffness_matrix(), body.mass_matrix(), keep, n, first_row, n_rows,
                          several ? communicator : MPI_COMM_SELF, K_kept, M_kept);
        K_ptr = &K_kept;
        M_ptr = &M_kept;
        if (several) base::release_free_heap(); // the copies' work space, before MUMPS's analysis
        base::probe_memory("clamped K and M made");
      }
  }
  /// The matrices of the kept dofs (the body's own if nothing is clamped).
  const TrilinosWrappers::SparseMatrix &K() const { return *K_ptr; }
  const TrilinosWrappers::SparseMatrix &M() const { return *M_ptr; }
  unsigned int size() const { return kept.size(); }
  /// True on every process of a distributed reduction (some may own no row of a tiny body).
  bool distributed() const { return several; }
  /// The factor's estimated size on the process that holds most of it [bytes]; 0 if not made.
  double factor_bytes() const { return largest(factor ? factor->memory_estimate_bytes() : 0.0); }
  /// The most any process held when the factorisation started (the body model) [bytes].
  double held_before_factor_bytes() const { return largest(factor ? factor->resident_bytes_before() : 0.0); }
  /// The factor of K (of the kept dofs), made on first use: Cholesky on one process, MUMPS's
  /// LDL^T on several.
  const SparseFactorization &factorization()
  {
    if (!factor) factor = std::make_unique<SparseFactorization>(K(), M(), 0.0, distributed() ? "mumps" : "cholmod");
    return *factor;
  }
  /// x_c = K_c^{-1} b_c for body-dof loads b_c (zero on the clamped dofs), all in one solve.
  std::vector<Vector<double>> solve_many(const std::vector<Vector<double>> &loads)
  {
    const std::size_t m = n_rows, k = loads.size();
    std::vector<double> B(m * k), X(m * k);
    for (std::size_t c = 0; c < k; ++c)
      for (std::size_t j = 0; j < m; ++j) B[c * m + j] = loads[c][kept[first_row + j]];
    if (k > 0) factorization().solve_many(B.data(), X.data(), k);
    std::vector<Vector<double>> x(k, Vector<double>(keep.size()));
    if (!distributed())
      {
        for (std::size_t c = 0; c < k; ++c)
          for (std::size_t j = 0; j < m; ++j) x[c][kept[j]] = X[c * m + j];
        return x;
      }
    // Each process solved its block of rows; every one continues with the whole solution: one
    // gather of all blocks (each process' k columns one after the other), not k sums of
    // whole-length vectors that are zero but for one block.
    const std::vector<unsigned int> firsts = Utilities::MPI::all_gather(communicator, first_row),
                                    counts = Utilities::MPI::all_gather(communicator, n_rows);
    std::vector<int> sizes(counts.size()), offsets(counts.size() + 1, 0);
    for (std::size_t p = 0; p < counts.size(); ++p)
      {
        const std::size_t size = static_cast<std::size_t>(counts[p]) * k;
        AssertThrow(size + offsets[p] <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
                    ExcMessage("the static modes of this body are too many for one MPI message"));
        sizes[p] = static_cast<int>(size);
        offsets[p + 1] = offsets[p] + sizes[p];
      }
    std::vector<double> all(offsets.back());
    MPI_Allgatherv(X.data(), static_cast<int>(m * k), MPI_DOUBLE, all.data(), sizes.data(), offsets.data(), MPI_DOUBLE,
                   communicator);
    for (std::size_t p = 0; p < counts.size(); ++p)
      for (std::size_t c = 0; c < k; ++c)
        for (std::size_t j = 0; j < counts[p]; ++j)
          x[c][kept[firsts[p] + j]] = all[offsets[p] + c * counts[p] + j];
    return x;
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
  double largest(const double here) const { return distributed() ? Utilities::MPI::max(here, communicator) : here; }
  MPI_Comm communicator;
  unsigned int first_row = 0, n_rows = 0; ///< this process' block of the kept dofs
  bool several = false;
  TrilinosWrappers::SparseMatrix K_kept, M_kept;
  const TrilinosWrappers::SparseMatrix *K_ptr, *M_ptr;
  std::unique_ptr<SparseFactorization> factor;
};

/// An M-orthonormal set of vectors with their products M b, so that Gram-Schmidt needs one
/// matrix product per new vector (b_j^T M v = (M b_j)^T v).
struct MOrthonormalSet
{
  std::vector<Vector<double>> vectors, M_vectors;
  /// Appends v made M-orthogonal to @p against and to this set (classical Gram-Schmidt, twice:
  /// Kahan's "twice is enough") unless it is dependent within 1e-8; returns whether it was kept.
  bool append(Vector<double> v, const MOrthonormalSet &against, const fem::BodyModel &body)
  {
    Vector<double> Mv(v.size());
    body.mass_vmult(Mv, v);
    const double original = std::sqrt(v * Mv);
    if (!(original > 0)) return false;
    for (int pass = 0; pass < 2; ++pass)
      for (const MOrthonormalSet *set : {&against, static_cast<const MOrthonormalSet *>(this)})
        {
          std::vector<double> c(set->vectors.size());
          for (unsigned int j = 0; j < c.size(); ++j) c[j] = set->M_vectors[j] * v;
          for (unsigned int j = 0; j < c.size(); ++j) v.add(-c[j], set->vectors[j]);
        }
    body.mass_vmult(Mv, v);
    const double norm = std::sqrt(v * Mv);
    if (!(norm > 1e-8 * original)) return false;
    v /= norm;
    Mv /= norm;
    vectors.push_back(std::move(v));
    M_vectors.push_back(std::move(Mv));
    return true;
  }
};

/// Rigid-body modes, M-orthonormal.
MOrthonormalSet orthonormal_rigid_modes(const fem::BodyModel &body)
{
  MOrthonormalSet R;
  const MOrthonormalSet none;
  for (auto &r : body.rigid_body_modes()) R.append(r, none, body);
  AssertThrow(R.vectors.size() == 6, ExcMessage("the body's rigid-body modes are dependent (all nodes on one line?)"));
  return R;
}

/// f - M R R^T f: a load balanced by the rigid-body inertia forces it causes.
Vector<double> inertia_relief(const Vector<double> &f, const MOrthonormalSet &R)
{
  Vector<double> g = f;
  for (unsigned int j = 0; j < R.vectors.size(); ++j) g.add(-(R.vectors[j] * f), R.M_vectors[j]);
  return g;
}
/// The 12 unit inertial load cases (ReducedBasis::geometric_stiffness): static solution with
/// the body's supports (a free body: held at its first interface), the arms' geometric stiffness
/// of that state, projected on the modes.
/// No inertia relief: the multibody engine combines these cases with the body frame's actual
/// angular velocity, angular acceleration and origin acceleration, and that combination is
/// balanced by itself for a free-flying body and by the joint's reaction for a held one. Relieving
/// each unit case instead removed the reaction of a body held at its interface: a beam spinning
/// about its root lost its root tension (flap 1 at W = 10: 7.03 instead of 11.20, Wright et al.).
std::vector<FullMatrix<double>> geometric_stiffness_of_inertial_loads(const fem::BodyModel &body,
                                                                      const std::vector<Vector<double>> &modes)
{
  std::vector<unsigned int> hold;
  if (!body.is_supported())
    {
      if (body.interfaces().empty())
        throw InputError("Reduction/Geometric stiffness", "a free body needs an interface to hold it in the static "
                                                           "solves of its inertial loads; add one, or support the body");
      hold.assign(body.interfaces()[0].dofs.begin(), body.interfaces()[0].dofs.end());
    }
  ClampedBody held(body, hold);
  const auto &nodes = body.full_nodes();
  std::vector<Vector<double>> loads;
  for (unsigned int c = 0; c < 12; ++c)
    {
      Tensor<2, 3> W;
      if (c < 3)
        W[c][c] = 1;
      else if (c < 6)
        {
          const unsigned int a = c == 5 ? 1 : 0, b = c == 3 ? 1 : 2;
          W[a][b] = W[b][a] = 1;
        }
      Vector<double> field(body.n_full_dofs()), f(body.n_full_dofs());
      for (const auto &node : nodes)
        {
          const Tensor<1, 3> x(node.x);
          Tensor<1, 3> v; // inertial force per unit mass
          if (c < 6)
            v = trace(W) * x - W * x; // -omega x (omega x x) for W = omega omega^T
          else if (c < 9)
            v[c - 6] = -1;
          else
            v = -cross_product_3d(Tensor<1, 3>(Point<3>::unit_vector(c - 9)), x);
          for (unsigned int d = 0; d < 3; ++d) field[node.u[d]] = v[d];
        }
      body.full_mass_vmult(f, field);
      loads.push_back(body.condense(f));
    }
  const auto states = held.solve_many(loads);
  std::vector<Vector<double>> full_modes;
  for (const auto &m : modes) full_modes.push_back(body.expand(m));
  const unsigned int n = modes.size();
  std::vector<FullMatrix<double>> G(12, FullMatrix<double>(n, n));
  for (unsigned int c = 0; c < 12; ++c)
    {
      const Vector<double> u = body.expand(states[c]);
      for (unsigned int a = 0; a < body.n_arms(); ++a)
        {
          const auto &arm = body.arm_model(a);
          const unsigned int offset = body.arm_offset(a), m = arm.n_dofs();
          Vector<double> ua(m), pa(m), Gp(m);
          for (unsigned int i = 0; i < m; ++i) ua[i] = u[offset + i];
          TrilinosWrappers::SparseMatrix K_G;
          arm.geometric_stiffness(ua, K_G);
          std::vector<Vector<double>> arm_modes(n, Vector<double>(m));
          for (unsigned int k = 0; k < n; ++k)
            for (unsigned int i = 0; i < m; ++i) arm_modes[k][i] = full_modes[k][offset + i];
          for (unsigned int k = 0; k < n; ++k)
            {
              K_G.vmult(Gp, arm_modes[k]);
              for (unsigned int j = 0; j < n; ++j) G[c](j, k) += arm_modes[j] * Gp;
            }
        }
      G[c].symmetrize();
    }
  return G;
}
} // namespace

namespace
{
/// Indices of the arms named in Reduction/Track arms; refuses requests the body cannot meet.
std::vector<unsigned int> checked_track_arms(const fem::BodyModel &body, const ReductionSettings &settings,
                                             const ReductionMethod &method)
{
  if (!body.is_supported() && body.interfaces().empty() && (method.fixed_interface || !settings.track_arms.empty()))
    throw InputError("Body/Interfaces", "a free body reduced by " + method.title +
                                          (method.fixed_interface ? "" : " with track load modes") +
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
  return track_arms;
}

/// Dofs held fixed: every interface (fixed-interface method) or, for the static solves of a
/// free body, the frame interface.
std::vector<unsigned int> clamped_dofs(const fem::BodyModel &body, const ReductionMethod &method)
{
  std::vector<unsigned int> clamped;
  const auto &interfaces = body.interfaces();
  if (method.fixed_interface)
    for (const auto &p : interfaces) clamped.insert(clamped.end(), p.dofs.begin(), p.dofs.end());
  else if (!body.is_supported() && !interfaces.empty())
    clamped.assign(interfaces[0].dofs.begin(), interfaces[0].dofs.end());
  return clamped;
}

/// The normal modes (fixed- or free-interface) appended to @p basis, M-orthogonal to @p R.
void add_normal_modes(const fem::BodyModel &body, ClampedBody &anchored, const MOrthonormalSet &R,
                      const ReductionSettings &settings, const ReductionMethod &method, MOrthonormalSet &basis)
{
  const bool free_body = !body.is_supported();
  const unsigned int n_rigid = R.vectors.size();
  const unsigned int n_free = method.fixed_interface ? anchored.size() : body.n_dofs();
  if (settings.n_normal_modes + n_rigid >= n_free)
    {
      std::ostringstream m;
      m << settings.n_normal_modes << " normal modes requested, but the body has only " << n_free
        << " free degrees of freedom" << (n_rigid ? " (6 of them rigid-body motions)" : "")
        << "; allowed: fewer than " << n_free - n_rigid << ", or refine the mesh";
      throw InputError("Reduction/Number of normal modes", m.str());
    }
  if (settings.n_normal_modes == 0) return;
  ModalSettings modal = settings.modal;
  modal.n_modes = settings.n_normal_modes + n_rigid;
  // Free interfaces: the whole body (its own matrices on one process, distributed rows on several).
  std::optional<ClampedBody> whole;
  if (!method.fixed_interface) whole.emplace(body, std::vector<unsigned int>());
  const auto &K_eig = method.fixed_interface ? anchored.K() : whole->K();
  const auto &M_eig = method.fixed_interface ? anchored.M() : whole->M();
  // Fixed interfaces: K is positive definite, so shift 0 works and one Cholesky factor serves the
  // eigen solve and all static solves.
  const bool share = method.fixed_interface && std::isnan(modal.shift) &&
                     (modal.direct_solver == "auto" || modal.direct_solver == "cholmod");
  const Modes modes = share ? lowest_modes(K_eig, M_eig, n_free, modal, 0.0, anchored.factorization())
                            : lowest_modes(K_eig, M_eig, n_free, modal);
  if (n_rigid == 0 && modes.eigenvalues[0] < 1e-10 * std::abs(modes.eigenvalues.back()))
    throw SolverError("the " + std::string(free_body ? "body, held at its first interface," : "supported body") +
                      " still has a zero-energy mode (eigenvalue " + std::to_string(modes.eigenvalues[0]) +
                      " rad^2/s^2): a mechanism; check Body/Ties (a region that cannot carry the arm root's "
                      "rotation) and the supports");
  // The six near-zero modes of a free body are the rigid-body motions (replaced by the exact R);
  // a seventh near-zero eigenvalue means a part that is not connected.
  if (n_rigid > 0 && std::abs(modes.eigenvalues[6]) < 1e-8 * std::abs(modes.eigenvalues.back()))
    throw SolverError("the free body has more than six zero-energy modes (eigenvalue " +
                      std::to_string(modes.eigenvalues[6]) + " rad^2/s^2): a part is not tied to the rest; "
                      "check Body/Ties");
  for (unsigned int i = n_rigid; i < modes.shapes.size(); ++i)
    basis.append(method.fixed_interface ? anchored.expand(modes.shapes[i]) : modes.shapes[i], R, body);
}

/// The static vectors: interface constraint modes (fixed interface) or residual attachment modes
/// (free interface), then track load modes; all solved with the one factorisation.
void add_static_modes(const fem::BodyModel &body, ClampedBody &anchored, const MOrthonormalSet &R,
                      const ReductionSettings &settings, const ReductionMethod &method,
                      const std::vector<unsigned int> &track_arms, MOrthonormalSet &basis, ReducedBasis &r)
{
  const auto &interfaces = body.interfaces();
  const bool relieve = !R.vectors.empty();
  std::vector<Vector<double>> loads;
  std::vector<int> prescribed; // fixed interface: the interface dof set to 1, else -1
  std::vector<bool> is_track;
  for (unsigned int p = 0; p < interfaces.size(); ++p)
    {
      if (method.fixed_interface && !body.is_supported() && p == 0) continue; // the body frame
      for (const auto dof : interfaces[p].dofs)
        {
          Vector<double> f(body.n_dofs());
          if (method.fixed_interface)
            {
              // u = e_j on the interface, K_oo u_o = -K_oj elsewhere.
              Vector<double> e(body.n_dofs());
              e[dof] = 1;
              body.stiffness_vmult(f, e);
              f *= -1;
            }
          else
            f[dof] = 1;
          loads.push_back(relieve ? inertia_relief(f, R) : f);
          prescribed.push_back(method.fixed_interface ? static_cast<int>(dof) : -1);
          is_track.push_back(false);
        }
    }
  std::vector<int> track_arm_of_load(loads.size(), -1); // the arm of each track load, -1 for the others
  for (const auto a : track_arms)
    {
      const double L = body.arm_model(a).arm().curve->length();
      for (unsigned int k = 1; k <= settings.n_stations; ++k)
        for (unsigned int d = 0; d < 3; ++d)
          {
            const Vector<double> f = body.arm_point_load(a, k * L / settings.n_stations, Tensor<1, 3>(Point<3>::unit_vector(d)));
            loads.push_back(relieve ? inertia_relief(f, R) : f);
            prescribed.push_back(-1);
            is_track.push_back(true);
            track_arm_of_load.push_back(static_cast<int>(a));
          }
    }
  auto responses = anchored.solve_many(loads);
  loads.clear();
  r.track_stations.assign(body.n_arms(), 0); // Track stations of an arm with a track vector kept
  for (unsigned int i = 0; i < responses.size(); ++i)
    {
      if (prescribed[i] >= 0) responses[i][prescribed[i]] = 1;
      if (!basis.append(std::move(responses[i]), R, body))
        ++r.n_dropped;
      else if (is_track[i])
        {
          ++r.n_track;
          r.track_stations[track_arm_of_load[i]] = settings.n_stations;
        }
      else
        ++r.n_interface;
    }
}

/// Rotates @p basis onto the reduced eigenvectors: Phi^T M Phi = 1, Phi^T K Phi = diag(w^2).
/// K_r and M_r come from the stored products; the rotated ones are V^T K_r V and V^T M_r V.
void diagonalise(const fem::BodyModel &body, const MOrthonormalSet &basis, ReducedBasis &r)
{
  const unsigned int n = basis.vectors.size();
  LAPACKFullMatrix<double> Kr(n), Mr(n);
  {
    Vector<double> Kb(body.n_dofs());
    for (unsigned int b = 0; b < n; ++b)
      {
        body.stiffness_vmult(Kb, basis.vectors[b]);
        for (unsigned int a = 0; a < n; ++a) Kr(a, b) = basis.vectors[a] * Kb;
      }
  }
  for (unsigned int a = 0; a < n; ++a)
    for (unsigned int b = 0; b < n; ++b) Mr(a, b) = basis.vectors[a] * basis.M_vectors[b];
  for (unsigned int a = 0; a < n; ++a)
    for (unsigned int b = 0; b < a; ++b)
      {
        Kr(a, b) = Kr(b, a) = 0.5 * (Kr(a, b) + Kr(b, a));
        Mr(a, b) = Mr(b, a) = 0.5 * (Mr(a, b) + Mr(b, a));
      }
  FullMatrix<double> K_basis(n, n), M_basis(n, n); // before LAPACK overwrites Kr, Mr
  for (unsigned int a = 0; a < n; ++a)
    for (unsigned int b = 0; b < n; ++b)
      {
        K_basis(a, b) = Kr(a, b);
        M_basis(a, b) = Mr(a, b);
      }
  std::vector<Vector<double>> V(n, Vector<double>(n));
  if (n > 0) Kr.compute_generalized_eigenvalues_symmetric(Mr, V);
  std::vector<unsigned int> order(n);
  for (unsigned int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](unsigned int i, unsigned int j) { return Kr.eigenvalue(i).real() < Kr.eigenvalue(j).real(); });
  FullMatrix<double> T(n, n); // column i = V[order[i]]
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int b = 0; b < n; ++b) T(b, i) = V[order[i]][b];
  r.modes.assign(n, Vector<double>(body.n_dofs()));
  for (unsigned int i = 0; i < n; ++i)
    for (unsigned int b = 0; b < n; ++b) r.modes[i].add(T(b, i), basis.vectors[b]);
  r.stiffness.reinit(n, n);
  r.mass.reinit(n, n);
  r.stiffness.triple_product(K_basis, T, T, true, false);
  r.mass.triple_product(M_basis, T, T, true, false);
}

/// C = alpha M + beta K + diag(2 zeta w_i m_i).
void add_damping(const ReductionSettings &settings, ReducedBasis &r)
{
  const unsigned int n = r.mass.m();
  r.damping.reinit(n, n);
  for (unsigned int a = 0; a < n; ++a)
    for (unsigned int b = 0; b < n; ++b)
      r.damping(a, b) = settings.rayleigh_mass * r.mass(a, b) + settings.rayleigh_stiffness * r.stiffness(a, b);
  for (unsigned int a = 0; a < n; ++a)
    r.damping(a, a) += 2 * settings.damping_ratio * std::sqrt(std::max(0.0, r.stiffness(a, a) / r.mass(a, a))) * r.mass(a, a);
}
} // namespace

const std::vector<ReductionMethod> &reduction_methods()
{
  // The central table: the parameter "Reduction/Method" selects a row by name.
  static const std::vector<ReductionMethod> methods{
    {ReductionSettings::Method::craig_bampton, "craig bampton", "Craig-Bampton",
     "fixed-interface normal modes plus interface constraint modes", true},
    {ReductionSettings::Method::free_interface, "free interface", "free-interface modes",
     "free-interface normal modes plus residual attachment modes (inertia relief and a mean-axis body frame "
     "for a free body)", false}};
  return methods;
}

const ReductionMethod &reduction_method(const ReductionSettings::Method m)
{
  for (const auto &row : reduction_methods())
    if (row.method == m) return row;
  Assert(false, ExcInternalError());
  return reduction_methods()[0];
}

ReducedBasis reduce(const fem::BodyModel &body, const ReductionSettings &settings, TimerOutput *timer)
{
  const ReductionMethod &method = reduction_method(settings.method);
  const auto track_arms = checked_track_arms(body, settings, method);
  std::optional<TimerOutput::Scope> stage; // one timing mechanism: the caller's TimerOutput
  auto start = [&](const char *name) {
    stage.reset();
    if (timer) stage.emplace(*timer, std::string("reduce: ") + name);
  };
  start("clamp and factorise");
  ClampedBody anchored(body, clamped_dofs(body, method));
  // Mean-axis frame (free-interface method, free body): every vector M-orthogonal to R.
  const bool mean_axes = !method.fixed_interface && !body.is_supported();
  const MOrthonormalSet R = mean_axes ? orthonormal_rigid_modes(body) : MOrthonormalSet();
  ReducedBasis r;
  MOrthonormalSet basis;
  start("eigen solve");
  add_normal_modes(body, anchored, R, settings, method, basis);
  r.n_normal = basis.vectors.size();
  start("static modes");
  add_static_modes(body, anchored, R, settings, method, track_arms, basis, r);
  // An empty basis is allowed: the rigid limit of the body (its inertia only).
  start("project and diagonalise");
  diagonalise(body, basis, r);
  if (settings.geometric_stiffness)
    {
      start("geometric stiffness");
      r.geometric_stiffness = geometric_stiffness_of_inertial_loads(body, r.modes);
    }
  stage.reset();
  add_damping(settings, r);
  r.factor_bytes = anchored.factor_bytes();
  r.held_before_factor_bytes = anchored.held_before_factor_bytes();
  return r;
}

std::vector<double> full_model_frequencies_hz(const fem::BodyModel &body, const ReductionSettings &settings,
                                              const unsigned int n)
{
  const bool free_body = !body.is_supported();
  const bool craig_bampton = settings.method == ReductionSettings::Method::craig_bampton;
  std::vector<unsigned int> clamped;
  if (free_body && craig_bampton && !body.interfaces().empty())
    clamped.assign(body.interfaces()[0].dofs.begin(), body.interfaces()[0].dofs.end());
  const ClampedBody model(body, clamped);
  const unsigned int n_rigid = (free_body && clamped.empty()) ? 6 : 0;
  ModalSettings modal = settings.modal;
  modal.n_modes = std::min(n + n_rigid, model.size() - 1);
  const Modes modes = lowest_modes(model.K(), model.M(), model.size(), modal);
  std::vector<double> f;
  for (unsigned int i = n_rigid; i < modes.eigenvalues.size(); ++i) f.push_back(frequency_hz(modes.eigenvalues[i]));
  return f;
}
} // namespace flextrack::reduction
