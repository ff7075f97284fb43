#include <base/solver_error.h>
#include <reduction/mumps_factor.h>

#include <Epetra_CrsMatrix.h>
#include <Epetra_MpiComm.h>
#include <dmumps_c.h>
#include <mpi.h>

#include <algorithm>
#include <climits>
#include <string>
#include <vector>

namespace flextrack::reduction
{
struct MumpsFactor::Instance
{
  mutable DMUMPS_STRUC_C id{}; // mutable: MUMPS writes its statistics on every call, solves too
  MPI_Comm communicator = MPI_COMM_NULL;
  bool host = false;               // rank 0: MUMPS's host, which holds the right-hand sides
  unsigned int n_rows = 0;         // A's rows on this process
  std::vector<int> irn, jcn;       // this process' upper triangle, 1-based (MUMPS's convention)
  std::vector<double> values;      // its entries
  std::vector<int> counts, firsts; // host: each process' number of rows and first in all_rows
  std::vector<int> all_rows;       // host: the global rows of every process, process by process
  std::size_t host_numbers = 0;    // the most numbers the host's dense buffers take at once
  bool factorized = false;
  mutable std::vector<double> gathered, dense;

  /// Runs MUMPS's phase @p job; returns INFOG(1) (< 0: an error, the same on every process).
  int run(const int job) const
  {
    id.job = job;
    dmumps_c(&id);
    return id.infog[0];
  }

  /// Runs MUMPS's phase @p job and turns a MUMPS error into a SolverError that says what it was
  /// doing.
  void call(const int job, const char *what) const
  {
    if (run(job) >= 0) return;
    throw error(what);
  }

  /// The SolverError for the last phase's INFOG(1) < 0, with what to change.
  SolverError error(const char *what) const
  {
    const int code = id.infog[0], detail = id.infog[1];
    std::string message = std::string("MUMPS failed in its ") + what + " (INFOG(1) = " + std::to_string(code) +
                          ", INFOG(2) = " + std::to_string(detail) + "): ";
    if (code == -10)
      message += "the matrix is singular (a shift equal to an eigenvalue, or a structure with a mechanism); "
                 "change 'Modal analysis/Shift' or the supports";
    else if (code == -13 || code == -19)
      message += "it ran out of memory; run on more processes or machines, or use a coarser mesh";
    else if (code == -8 || code == -9 || code == -14)
      message += "its work space was too small even after enlarging it (delayed pivots of an indefinite matrix); "
                 "change 'Modal analysis/Shift'";
    else
      message += "see the MUMPS user guide for this code";
    return SolverError(message);
  }

  ~Instance()
  {
    if (id.job != 0) // initialised (JOB = -1 was called): free MUMPS's own data
      {
        id.job = -2;
        dmumps_c(&id);
      }
  }
};

MumpsFactor::MumpsFactor(const Epetra_CrsMatrix &A, const std::size_t host_numbers)
  : instance(std::make_unique<Instance>())
{
  Instance &m = *instance;
  m.host_numbers = std::max<std::size_t>(host_numbers, 1);
  m.communicator = dynamic_cast<const Epetra_MpiComm &>(A.Comm()).Comm();
  int rank = 0, size = 1;
  MPI_Comm_rank(m.communicator, &rank);
  MPI_Comm_size(m.communicator, &size);
  m.host = rank == 0;
  m.n_rows = A.NumMyRows();

  // The upper triangle of this process' rows (MUMPS sums an entry given twice, so only one
  // triangle of a symmetric matrix is handed over): counted first, so that the triplets, half
  // the matrix, are allocated once at their size.
  std::vector<int> my_rows(m.n_rows);
  bool readable = true;
  std::size_t n_upper = 0;
  for (const bool fill : {false, true})
    {
      if (fill)
        {
          m.irn.reserve(n_upper);
          m.jcn.reserve(n_upper);
          m.values.reserve(n_upper);
        }
      for (unsigned int i = 0; i < m.n_rows && readable; ++i)
        {
          const long long row = A.GRID64(i);
          my_rows[i] = static_cast<int>(row);
          int n_entries = 0;
          double *entries = nullptr;
          int *columns = nullptr;
          readable = A.ExtractMyRowView(i, n_entries, entries, columns) == 0;
          for (int e = 0; e < n_entries && readable; ++e)
            {
              const long long column = A.GCID64(columns[e]);
              if (column < row) continue;
              if (!fill)
                {
                  ++n_upper;
                  continue;
                }
              m.irn.push_back(static_cast<int>(row + 1));
              m.jcn.push_back(static_cast<int>(column + 1));
              m.values.push_back(entries[e]);
            }
        }
    }
  // Decided on every process, before the collectives below.
  int all_readable = readable ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &all_readable, 1, MPI_INT, MPI_MIN, m.communicator);
  if (!all_readable) throw SolverError("MUMPS: the rows of the matrix could not be read (not filled)");

  // The host learns which rows each process holds: right-hand sides are gathered there.
  const int n_mine = static_cast<int>(m.n_rows);
  if (m.host) m.counts.resize(size);
  MPI_Gather(&n_mine, 1, MPI_INT, m.counts.data(), 1, MPI_INT, 0, m.communicator);
  if (m.host)
    {
      m.firsts.assign(size, 0);
      for (int p = 1; p < size; ++p) m.firsts[p] = m.firsts[p - 1] + m.counts[p - 1];
      m.all_rows.resize(m.firsts[size - 1] + m.counts[size - 1]);
    }
  MPI_Gatherv(my_rows.data(), n_mine, MPI_INT, m.all_rows.data(), m.counts.data(), m.firsts.data(), MPI_INT, 0,
              m.communicator);

  m.id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(m.communicator));
  m.id.par = 1; // the host works on the factor too
  m.id.sym = 2; // symmetric, not necessarily positive definite: LDL^T with pivoting
  m.call(-1, "initialisation");
  m.id.icntl[0] = -1; // no error messages on Fortran units: errors are reported by the caller
  m.id.icntl[1] = -1; // no diagnostics
  m.id.icntl[2] = -1; // no global information
  m.id.icntl[3] = 0;
  m.id.icntl[9] = 0;  // ICNTL(10) = 0: no iterative refinement, and
  m.id.icntl[10] = 0; // ICNTL(11) = 0: no error analysis; the solves then need only the factor
  m.id.icntl[17] = 3; // ICNTL(18) = 3: the matrix is given distributed, each process its triplets
  m.id.icntl[19] = 0; // ICNTL(20) = 0: dense right-hand sides, on the host
  m.id.icntl[20] = 0; // ICNTL(21) = 0: the solution centralised on the host
  m.id.icntl[27] = 1; // ICNTL(28) = 1: sequential analysis (Debian's MUMPS has no parallel ordering)
  m.id.n = static_cast<MUMPS_INT>(A.NumGlobalRows64());
  m.id.nnz_loc = static_cast<MUMPS_INT8>(m.values.size());
  m.id.nz_loc = m.values.size() <= static_cast<std::size_t>(INT_MAX) ? static_cast<MUMPS_INT>(m.values.size()) : 0;
  m.id.irn_loc = m.irn.data();
  m.id.jcn_loc = m.jcn.data();
  m.id.a_loc = m.values.data();
  m.call(1, "analysis");
}

MumpsFactor::~MumpsFactor() = default;

double MumpsFactor::estimated_bytes() const
{
  // INFO(15): this process' memory for the factorisation in core [10^6 bytes]; INFO(3) and
  // INFO(4): the factor's reals and integers (a negative value counts millions).
  const auto &info = instance->id.info;
  auto count = [](const int v) { return v < 0 ? -1e6 * v : static_cast<double>(v); };
  return std::max(1e6 * info[14], 8 * count(info[2]) + 4 * count(info[3]));
}

void MumpsFactor::factorize()
{
  Instance &m = *instance;
  if (m.factorized) throw SolverError("MUMPS: the matrix was factorised already (its entries are freed)");
  // An indefinite matrix may delay pivots beyond the work space the analysis foresaw (INFOG(1)
  // = -8 or -9, -14 for integers): enlarged by ICNTL(14) percent, up to three times, as the
  // MUMPS user guide advises. The matrix's entries are still here for another try.
  for (int attempt = 0;; ++attempt)
    {
      const int status = m.run(2);
      if (status >= 0) break;
      if ((status != -8 && status != -9 && status != -14) || attempt == 3) throw m.error("factorisation");
      m.id.icntl[13] = std::max(2 * m.id.icntl[13], 40); // ICNTL(14): the work space's relaxation [%]
    }
  m.factorized = true;
  // The solves need only the factor (no iterative refinement, no error analysis): the triplets,
  // a copy of half the matrix, are given back.
  m.id.irn_loc = m.id.jcn_loc = nullptr;
  m.id.a_loc = nullptr;
  std::vector<int>().swap(m.irn);
  std::vector<int>().swap(m.jcn);
  std::vector<double>().swap(m.values);
}

void MumpsFactor::solve_many(const double *B, double *X, const unsigned int k) const
{
  // The host holds two dense copies of the columns it solves at once: at most 2^24 numbers each
  // (128 MiB), which also keeps MPI's int counts in range.
  const std::size_t n_global = instance->id.n > 0 ? instance->id.n : 1;
  const auto chunk = static_cast<unsigned int>(std::clamp<std::size_t>(instance->host_numbers / n_global, 1, INT_MAX / n_global));
  const std::size_t m = instance->n_rows;
  for (unsigned int first = 0; first < k; first += chunk)
    solve_columns(B + first * m, X + first * m, std::min(chunk, k - first));
}

void MumpsFactor::solve_columns(const double *B, double *X, const unsigned int k) const
{
  const Instance &m = *instance;
  // MUMPS takes dense right-hand sides on the host (ICNTL(20) = 0) and puts the solutions there
  // (ICNTL(21) = 0): each process' k columns are gathered there in one message, put in the
  // global order, solved together, and sent back the same way.
  const std::size_t n = m.host ? m.all_rows.size() : 0;
  std::vector<int> counts_k, firsts_k;
  if (m.host)
    for (std::size_t p = 0; p < m.counts.size(); ++p)
      {
        counts_k.push_back(m.counts[p] * static_cast<int>(k));
        firsts_k.push_back(m.firsts[p] * static_cast<int>(k));
      }
  m.gathered.resize(n * k);
  MPI_Gatherv(B, static_cast<int>(m.n_rows * k), MPI_DOUBLE, m.gathered.data(), counts_k.data(), firsts_k.data(),
              MPI_DOUBLE, 0, m.communicator);
  // Process p's block: its rows (all_rows[firsts[p] + j]) for column c at firsts[p] k + c counts[p] + j.
  auto each_entry = [&](auto &&visit) {
    for (std::size_t p = 0; p < m.counts.size(); ++p)
      for (unsigned int c = 0; c < k; ++c)
        for (int j = 0; j < m.counts[p]; ++j)
          visit(static_cast<std::size_t>(m.firsts[p]) * k + static_cast<std::size_t>(c) * m.counts[p] + j,
                static_cast<std::size_t>(c) * n + m.all_rows[m.firsts[p] + j]);
  };
  if (m.host)
    {
      m.dense.resize(n * k);
      each_entry([&](const std::size_t from, const std::size_t to) { m.dense[to] = m.gathered[from]; });
      m.id.rhs = m.dense.data();
      m.id.lrhs = static_cast<MUMPS_INT>(n);
    }
  m.id.nrhs = static_cast<MUMPS_INT>(k);
  m.call(3, "solve");
  if (m.host) each_entry([&](const std::size_t to, const std::size_t from) { m.gathered[to] = m.dense[from]; });
  MPI_Scatterv(m.gathered.data(), counts_k.data(), firsts_k.data(), MPI_DOUBLE, X, static_cast<int>(m.n_rows * k),
               MPI_DOUBLE, 0, m.communicator);
  if (k > 1) // the buffers of one column stay for the eigen solve's many single solves
    {
      std::vector<double>().swap(m.gathered);
      std::vector<double>().swap(m.dense);
    }
}

int MumpsFactor::negative_pivots() const
{
  return instance->id.infog[11];
}

} // namespace flextrack::reduction
