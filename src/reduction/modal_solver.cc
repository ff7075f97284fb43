#include <base/input_error.h>
#include <base/memory.h>
#include <base/text.h>
#include <reduction/block_lanczos.h>
#include <reduction/modal_solver.h>
#include <reduction/sparse_factorization.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/parpack_solver.h> // declares PARPACK's pdsaupd_ / pdseupd_
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/trilinos_vector.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_MultiVector.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <new>
#include <numeric>
#include <sstream>

namespace flextrack::reduction
{
using namespace dealii;

void ModalSettings::declare_parameters(ParameterHandler &prm)
{
  prm.enter_subsection("Modal analysis");
  prm.declare_entry("Number of modes", "10", Patterns::Integer(1),
                    "How many of the lowest natural modes to compute [-], 1 to 10000 (rigid-body modes count).");
  prm.declare_entry("Shift", "auto", Patterns::Anything(),
                    "Spectral shift sigma [rad^2/s^2], -1e16 to 1e16: the modes nearest sigma are found. 'auto' = minus the "
                    "square of an estimate of the first bending frequency, which yields the lowest modes "
                    "and keeps free structures factorisable.");
  prm.declare_entry("Tolerance", "1e-12", Patterns::Double(0), "Relative accuracy of the eigenvalues [-], > 0 and < 1.");
  prm.declare_entry("Maximum iterations", "1000", Patterns::Integer(1), "Maximum Lanczos restarts [-], 1 to 1000000.");
  prm.declare_entry("Direct solver", "auto", Patterns::Selection("auto|cholmod|mumps|klu"),
                    "Sparse direct solver that factorises K - sigma M: 'cholmod' (supernodal Cholesky, "
                    "SuiteSparse; falls back to 'mumps' when K - sigma M is not positive definite), 'mumps' "
                    "(MUMPS, symmetric indefinite LDL^T; on several processes under MPI), 'klu' (Trilinos Amesos, LU). "
                    "'auto' = cholmod.");
  prm.declare_entry("Participation reference point", "0, 0, 0", Patterns::List(Patterns::Double(), 3, 3, ","),
                    "modes: the point x, y, z [m] through which the axes of the rotational participation "
                    "factors and effective masses (rx, ry, rz) pass; each coordinate at most 1e9 m in size.");
  prm.leave_subsection();
}

ModalSettings ModalSettings::parse_parameters(ParameterHandler &prm)
{
  ModalSettings s;
  prm.enter_subsection("Modal analysis");
  // Bounds: 10000 modes is far beyond any reduction basis; a shift beyond 1e16 rad^2/s^2
  // (16 MHz) or a tolerance of 1 or more is a unit mistake, and ARPACK would fail on it later
  // with a message that names no entry.
  s.n_modes = prm.get_integer("Number of modes");
  if (s.n_modes > 10000)
    throw InputError("Modal analysis/Number of modes", std::to_string(s.n_modes) + " modes; allowed: 1 to 10000");
  const std::string shift = prm.get("Shift");
  if (shift != "auto")
    {
      s.shift = base::parse_number(shift, "Modal analysis/Shift", "'auto' or a number [rad^2/s^2]");
      if (std::abs(s.shift) > 1e16)
        throw InputError("Modal analysis/Shift", shift + " rad^2/s^2; allowed: 'auto' or a number from -1e16 to 1e16");
    }
  s.tolerance = prm.get_double("Tolerance");
  if (!(s.tolerance > 0 && s.tolerance < 1))
    throw InputError("Modal analysis/Tolerance", prm.get("Tolerance") + "; allowed: > 0 and < 1");
  s.max_iterations = prm.get_integer("Maximum iterations");
  if (s.max_iterations > 1000000)
    throw InputError("Modal analysis/Maximum iterations", prm.get("Maximum iterations") + "; allowed: 1 to 1000000");
  s.direct_solver = prm.get("Direct solver");
  const std::string point = "Modal analysis/Participation reference point";
  s.participation_reference = base::parse_vector3(prm.get("Participation reference point"), point, "m");
  for (const double c : s.participation_reference)
    if (!(std::abs(c) <= 1e9)) // the bound of mesh coordinates (fem/raw_mesh.h)
      {
        std::ostringstream m;
        m << "coordinate " << c << " m; allowed: coordinates of at most 1e9 m in size";
        throw InputError(point, m.str());
      }
  prm.leave_subsection();
  return s;
}

double frequency_hz(const double eigenvalue)
{
  return std::copysign(std::sqrt(std::abs(eigenvalue)), eigenvalue) / (2 * M_PI);
}

std::vector<double> Modes::frequencies_hz() const
{
  std::vector<double> f;
  for (const double l : eigenvalues) f.push_back(frequency_hz(l));
  return f;
}

namespace
{
/// At most n_free - 1 modes: ARPACK needs a Krylov space larger than the wanted modes.
void check_number_of_modes(const ModalSettings &settings, const unsigned int n_free)
{
  if (settings.n_modes >= n_free)
    throw InputError("Modal analysis/Number of modes",
                     std::to_string(settings.n_modes) + " modes requested, but the model has only " +
                       std::to_string(n_free) + " free degrees of freedom; allowed: fewer than " +
                       std::to_string(n_free) + " (or refine the mesh)");
}
} // namespace

namespace
{
/// out = M in for @p k vectors one after the other, on this process' share of the dofs.
using LocalMassProduct = std::function<void(const double *in, double *out, unsigned int k)>;

/// ARPACK's implicitly restarted Lanczos (PARPACK, reverse communication) on the symmetric
/// generalised problem in shift-invert mode or, when @p standard, on the standard problem of
/// lanczos() below. The Krylov space lives in the free dofs (M vanishes on the supported ones).
/// Out: @p lambda (theta in the standard form), the vectors @p z, how many @p converged, and
/// ARPACK's restarts (@p iterations).
void arpack_lanczos(const MPI_Comm comm, const IndexSet &owned, const unsigned int n_free,
                    const ModalSettings &settings, const bool standard, const LocalMassProduct &apply_mass,
                    const SparseFactorization &factorization, std::vector<double> &lambda, std::vector<double> &z,
                    unsigned int &converged, int &iterations, const double shift)
{
  int n_local = owned.n_elements();
  int nev = settings.n_modes;
  auto apply_inverse = [&](const double *in, double *out) { factorization.solve(in, out); };
  int ncv = std::min<int>(n_free, std::max(2 * nev + 1, nev + 20));
  int ldv = n_local;
  int ido = 0, info = 1, lworkl = ncv * (ncv + 8);
  char bmat[2] = "G", which[3] = "LM";
  double tol = settings.tolerance;
  MPI_Fint fortran_comm = MPI_Comm_c2f(comm);
  // A smooth start vector, a function of the global index (the same for any distribution), in
  // the range of the operator: (K - sigma M)^{-1} M v, or L^{-1} P M P^T L^{-T} v.
  std::vector<double> resid(n_local), v(static_cast<std::size_t>(n_local) * ncv), workd(3 * static_cast<std::size_t>(n_local)),
    workl(lworkl), tmp(n_local), tmp2(standard ? n_local : 0);
  auto standard_operator = [&](const double *in, double *out) { // L^{-1} P M P^T L^{-T} in
    factorization.solve_upper(in, tmp.data());
    apply_mass(tmp.data(), tmp2.data(), 1);
    factorization.solve_lower(tmp2.data(), out);
  };
  {
    std::vector<double> start(n_local);
    unsigned int k = 0;
    for (const auto i : owned) start[k++] = 1.0 + 0.1 * std::sin(0.37 * i);
    if (standard)
      standard_operator(start.data(), resid.data());
    else
      {
        apply_mass(start.data(), tmp.data(), 1);
        apply_inverse(tmp.data(), resid.data());
      }
  }
  std::vector<int> iparam(11, 0), ipntr(14, 0);
  iparam[0] = 1;
  iparam[2] = settings.max_iterations;
  iparam[6] = standard ? 1 : 3;
  if (standard) bmat[0] = 'I';
  while (true)
    {
      pdsaupd_(&fortran_comm, &ido, bmat, &n_local, which, &nev, &tol, resid.data(), &ncv, v.data(), &ldv,
               iparam.data(), ipntr.data(), workd.data(), workl.data(), &lworkl, &info);
      double *in = workd.data() + ipntr[0] - 1, *out = workd.data() + ipntr[1] - 1;
      if (standard && (ido == -1 || ido == 1))
        standard_operator(in, out);
      else if (ido == -1)
        {
          apply_mass(in, tmp.data(), 1);
          apply_inverse(tmp.data(), out);
        }
      else if (ido == 1)
        apply_inverse(workd.data() + ipntr[2] - 1, out);
      else if (ido == 2)
        apply_mass(in, out, 1);
      else
        break;
    }
  if (info == 1)
    throw SolverError("the Lanczos iteration did not converge in " + std::to_string(settings.max_iterations) +
                      " restarts; raise 'Modal analysis/Maximum iterations' or 'Tolerance', or move 'Shift' "
                      "closer to the wanted frequencies");
  if (info < 0)
    throw SolverError("ARPACK dsaupd failed with code " + std::to_string(info));

  int rvec = 1, ldz = n_local;
  char howmany = 'A';
  std::vector<int> select(ncv, 1);
  lambda.assign(nev, 0.0);
  z.assign(static_cast<std::size_t>(n_local) * nev, 0.0);
  double sigma = shift;
  pdseupd_(&fortran_comm, &rvec, &howmany, select.data(), lambda.data(), z.data(), &ldz, &sigma, bmat, &n_local,
           which, &nev, &tol, resid.data(), &ncv, v.data(), &ldv, iparam.data(), ipntr.data(), workd.data(),
           workl.data(), &lworkl, &info);
  if (info != 0)
    throw SolverError("ARPACK dseupd failed with code " + std::to_string(info));

  converged = iparam[4];
  iterations = iparam[2];
  if (converged < static_cast<unsigned int>(nev))
    throw SolverError("only " + std::to_string(converged) + " of " + std::to_string(nev) +
                      " modes converged; raise 'Modal analysis/Maximum iterations'");
}

/// Shift-invert Lanczos on the dofs @p owned (of @p n_global) of this process of @p comm:
/// every process holds its share of the vectors, and ARPACK's parallel version (PARPACK) runs
/// the iteration on them (a serial problem lives on MPI_COMM_SELF). On one process with a
/// Cholesky factor, block Lanczos runs first unless @p least_memory.
Modes lanczos(const MPI_Comm comm, const IndexSet &owned, const std::size_t n_global, const unsigned int n_free,
              const ModalSettings &settings, const double shift, const LocalMassProduct &apply_mass,
              const SparseFactorization &factorization, const bool least_memory = false)
{
  const bool parallel = Utilities::MPI::n_mpi_processes(comm) > 1;
  int n_local = owned.n_elements();
  int nev = settings.n_modes;
  // With A = K - sigma M = P^T L L^T P in halves (one process, Cholesky), the iteration runs on
  // the standard problem L^{-1} P M P^T L^{-T} y = theta y, theta = 1 / (lambda - sigma),
  // phi = P^T L^{-T} y: one product with M per step. The generalised form (mode 3) needs about
  // three, for its M-inner products; its Krylov space is the same up to the change of variables.
  const bool standard = !parallel && factorization.has_halves();
  auto dot = [&](const double *u, const double *v) {
    return Utilities::MPI::sum(std::inner_product(u, u + n_local, v, 0.0), comm);
  };

  std::vector<double> lambda, z, tmp(n_local); // eigenvalues (theta in the standard form), vectors
  unsigned int converged = 0;
  int iterations = 0;
  // Block Lanczos (block_lanczos.h): the factor and M read once per block of vectors, not once
  // per vector. Blocks of 8, so that a free body's six equal rigid-body eigenvalues (and pairs of
  // equal bending modes) are found whole, not only through round-off. For the 20 modes of the
  // 1e5-dof link, blocks of 8 took 16 steps (128 vectors, 32 passes over the factor; ARPACK: 63
  // vectors, 126 passes; blocks of 4: 23 steps) (doc/benchmarks.md). The basis may grow to
  // 6 nev + 40 vectors (no restart), for at most 200 modes; beyond, or should that not be enough
  // or not fit in memory, ARPACK below takes over, restarting in less memory. Not where the
  // caller asks for the least memory (a solid's 'modes', whose M is applied cell by cell, which
  // a block does not make cheaper): there the larger basis cost 7 % of the peak (74k dofs: 722
  // against 675 MB) and no time.
  if (standard && !least_memory && nev <= 200)
    {
      const unsigned int block = 8;
      std::vector<double> upper, massed;
      auto standard_block = [&](const double *in, double *out, const unsigned int k) { // L^{-1} P M P^T L^{-T} in
        upper.resize(static_cast<std::size_t>(n_local) * k);
        massed.resize(upper.size());
        factorization.solve_upper(in, upper.data(), k);
        apply_mass(upper.data(), massed.data(), k);
        factorization.solve_lower(massed.data(), out, k);
      };
      const std::size_t max_basis = std::min<std::size_t>(n_free, 6 * std::size_t(nev) + 40);
      try
        {
          if (auto pairs = block_lanczos(standard_block, n_local, nev, block, max_basis, settings.tolerance))
            {
              lambda = std::move(pairs->values);
              z = std::move(pairs->vectors);
              converged = nev;
              iterations = pairs->block_steps;
            }
        }
      catch (const std::bad_alloc &)
        {
          // The basis did not fit: ARPACK's restarted iteration needs less.
        }
    }
  if (converged == 0)
    arpack_lanczos(comm, owned, n_free, settings, standard, apply_mass, factorization, lambda, z, converged, iterations,
                   shift);
  base::probe_memory("Lanczos done");
  if (standard)
    {
      // Back from theta and y to lambda and phi. No refinement of the Ritz vectors as mode 3's
      // dseupd does: that purification is for its semi-definite M-inner product; here the inner
      // product is Euclidean and OP symmetric, so the Ritz vectors of the wanted (non-zero) theta
      // are orthogonal to OP's null space (M's, the supported dofs) to round-off. Adding one step
      // of inverse iteration cost 7 % of the 74k-dof solid's run and 1 s of the 1e5-dof body's.
      // Eight vectors per pass over the factor (a pass is memory-bound: about as fast for eight
      // as for one), in eight vectors' room rather than a copy of all of them.
      for (unsigned int k = 0; k < converged; ++k) lambda[k] = shift + 1.0 / lambda[k];
      const std::size_t n = n_local;
      std::vector<double> y;
      for (unsigned int first = 0; first < converged; first += 8)
        {
          const unsigned int k = std::min(8u, converged - first);
          y.assign(z.begin() + first * n, z.begin() + (first + k) * n);
          factorization.solve_upper(y.data(), z.data() + first * n, k);
        }
    }
  std::vector<int> order(converged);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return lambda[a] < lambda[b]; });
  Modes modes;
  modes.iterations = iterations;
  for (const int k : order)
    {
      double *phi = z.data() + static_cast<std::size_t>(k) * n_local;
      apply_mass(phi, tmp.data(), 1);
      const double norm = std::sqrt(dot(phi, tmp.data()));
      // Mass-normalise; sign convention: the largest component is positive (reproducible runs).
      double largest = 0;
      for (int i = 0; i < n_local; ++i)
        if (std::abs(phi[i]) > std::abs(largest)) largest = phi[i];
      const double global_largest = Utilities::MPI::max(std::abs(largest), comm);
      const double sign_here = std::abs(largest) == global_largest ? (largest < 0 ? -1.0 : 1.0) : 0.0;
      const double sign = Utilities::MPI::max(sign_here, comm) > 0 ? 1.0 : -1.0;
      // The full vector on every process (output needs it), entries at their global indices.
      Vector<double> shape(n_global);
      unsigned int j = 0;
      for (const auto i : owned) shape[i] = sign * phi[j++] / norm;
      if (parallel) Utilities::MPI::sum(shape, comm, shape);
      modes.eigenvalues.push_back(lambda[k]);
      modes.shapes.push_back(std::move(shape));
    }
  return modes;
}
} // namespace

Modes lowest_modes(const TrilinosWrappers::SparseMatrix &K, const TrilinosWrappers::SparseMatrix &M,
                   const unsigned int n_free, const ModalSettings &settings, const double shift,
                   const SparseFactorization &factorization)
{
  // Works on the matrices' own distribution: every process holds its locally owned rows.
  const MPI_Comm comm = K.get_mpi_communicator();
  const IndexSet &owned = K.locally_owned_range_indices();
  const std::size_t n_local = owned.n_elements();
  // Epetra views of the caller's arrays: k vectors in one pass over M.
  auto apply_mass = [&](const double *in, double *out, const unsigned int k) {
    const Epetra_CrsMatrix &m = M.trilinos_matrix();
    const Epetra_MultiVector x(View, m.DomainMap(), const_cast<double *>(in), n_local, k);
    Epetra_MultiVector y(View, m.RangeMap(), out, n_local, k);
    AssertThrow(m.Multiply(false, x, y) == 0, ExcMessage("Epetra multiply failed"));
  };
  return lanczos(comm, owned, K.m(), n_free, settings, shift, apply_mass, factorization);
}

Modes lowest_modes(const TrilinosWrappers::SparseMatrix &K, const TrilinosWrappers::SparseMatrix &M,
                   const unsigned int n_free, const ModalSettings &settings, const double shift,
                   const std::string &direct_solver)
{
  check_number_of_modes(settings, n_free);
  // Factorise A = K - sigma M once (CHOLMOD is serial: in parallel MUMPS does the work).
  const bool parallel = Utilities::MPI::n_mpi_processes(K.get_mpi_communicator()) > 1;
  const SparseFactorization factorization(K, M, shift, parallel && direct_solver == "cholmod" ? "mumps" : direct_solver);
  return lowest_modes(K, M, n_free, settings, shift, factorization);
}

double automatic_shift(const fem::Arm &arm)
{
  const double L = arm.curve->length();
  const double EI = arm.material.youngs_modulus * std::min(arm.section.inertia_y, arm.section.inertia_z);
  const double w = 1.875104068711961 * 1.875104068711961 *
                   std::sqrt(EI / (arm.material.density * arm.section.area)) / (L * L);
  return -w * w;
}

Modes lowest_modes(const fem::CurvedBeamModel &model, const ModalSettings &settings)
{
  const double shift = std::isnan(settings.shift) ? automatic_shift(model.arm()) : settings.shift;
  return lowest_modes(model.stiffness_matrix(), model.mass_matrix(), model.n_free_dofs(), settings, shift,
                      settings.direct_solver == "auto" ? "cholmod" : settings.direct_solver);
}

double automatic_shift(const TrilinosWrappers::SparseMatrix &K, const TrilinosWrappers::SparseMatrix &M)
{
  // Each process reads the diagonal of its locally owned rows only (a distributed matrix stores
  // no other), and the maximum over all processes makes the shift the same on every one.
  double largest = 0;
  for (const auto i : K.locally_owned_range_indices())
    if (M.diag_element(i) > 0) largest = std::max(largest, K.diag_element(i) / M.diag_element(i));
  return -1e-6 * Utilities::MPI::max(largest, K.get_mpi_communicator());
}

Modes lowest_modes(const TrilinosWrappers::SparseMatrix &K, const TrilinosWrappers::SparseMatrix &M,
                   const unsigned int n_free, const ModalSettings &settings)
{
  const double shift = std::isnan(settings.shift) ? automatic_shift(K, M) : settings.shift;
  return lowest_modes(K, M, n_free, settings, shift, settings.direct_solver == "auto" ? "cholmod" : settings.direct_solver);
}

Modes lowest_modes(const fem::SolidModel &model, const ModalSettings &settings)
{
  return lowest_modes(model.stiffness_matrix(), model.mass_matrix(), model.n_free_dofs(), settings);
}

Modes lowest_modes_releasing_matrices(fem::SolidModel &model, const ModalSettings &settings)
{
  const auto &K = model.stiffness_matrix(), &M = model.mass_matrix();
  const double shift = std::isnan(settings.shift) ? automatic_shift(K, M) : settings.shift;
  const bool serial = Utilities::MPI::n_mpi_processes(K.get_mpi_communicator()) == 1;
  const bool cholesky = settings.direct_solver == "auto" || settings.direct_solver == "cholmod";
  // A shift of 0 or more may make K - sigma M singular or indefinite: that needs the fallback
  // to MUMPS, which needs K and M; under MPI, MUMPS factorises the distributed matrices.
  if (!serial || !cholesky || !(shift < 0)) return lowest_modes(model, settings);
  check_number_of_modes(settings, model.n_free_dofs());
  const SparseFactorization factorization(K, M, shift, [&] { model.release_matrices(); });
  // Made after the factor, so that its memory (a twentieth of the factor's) does not add to
  // the factorisation's peak.
  const fem::SolidMassOperator &mass = model.mass_operator();
  const std::size_t n = model.n_dofs();
  return lanczos(MPI_COMM_SELF, complete_index_set(n), n, model.n_free_dofs(), settings, shift,
                 [&](const double *in, double *out, const unsigned int k) {
                   for (unsigned int c = 0; c < k; ++c) mass.vmult(in + c * n, out + c * n);
                 },
                 factorization, true);
}
} // namespace flextrack::reduction
