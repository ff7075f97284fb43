#include <base/input_error.h>
#include <base/mpi_session.h>
#include <base/solver_error.h>
#include <fem/body_model.h>
#include <io/reduced_body_cache.h>
#include <io/output_folder.h>
#include <io/reduced_body_file.h>
#include <reduction/component_modes.h>
#include <reduction/plausibility.h>
#include <reduction/reduced_body_builder.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <deal.II/base/mpi.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <cerrno>
#include <memory>
#include <optional>
#include <sstream>

namespace flextrack::io
{
using dealii::TimerOutput;

namespace
{
/// An exclusive lock (flock) on a hidden FILE.lock beside the cached body while it is looked up
/// and, if stale, reduced and written: two processes that need the same body (the cases of a
/// sweep, two runs started at once) reduce it once; the second waits, then loads the file. A
/// folder created only for the lock is removed again when the body could not be obtained (a
/// failed run leaves nothing behind).
class CacheLock
{
public:
  CacheLock(const std::string &file, std::ostream &log)
  {
    const auto path = std::filesystem::path(file);
    folder = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    lock = folder / ("." + path.filename().string() + ".lock");
    bool said = false;
    for (int attempt = 0; attempt < 100; ++attempt)
      {
        std::error_code ec;
        if (!std::filesystem::exists(folder, ec)) created_folder = std::filesystem::create_directories(folder, ec) || created_folder;
        descriptor = ::open(lock.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
        if (descriptor < 0) return; // a read-only folder: no lock; writing the body reports the folder
        // A file system without flock (ENOLCK, EOPNOTSUPP): no lock; two processes may then reduce
        // the same body at once, each writing its file atomically.
        if (flock(descriptor, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK)
          {
            if (!said) log << "  waiting for another process that is reducing this body (" << file << ")" << std::endl;
            said = true;
            while (flock(descriptor, LOCK_EX) != 0 && errno == EINTR) {}
          }
        // The holder may have removed the lock file (a failed first reduction in a folder it
        // made): then this lock is on a file nobody else sees; lock the one at the path.
        struct stat held{}, named{};
        if (fstat(descriptor, &held) == 0 && ::stat(lock.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
            held.st_dev == named.st_dev)
          return;
        ::close(descriptor);
        descriptor = -1;
      }
  }
  void obtained() { success = true; }
  ~CacheLock()
  {
    std::error_code ec;
    if (!success && created_folder) std::filesystem::remove(lock, ec);
    if (descriptor >= 0) ::close(descriptor);
    if (!success && created_folder) std::filesystem::remove(folder, ec); // only if empty
  }
  CacheLock(const CacheLock &) = delete;
  CacheLock &operator=(const CacheLock &) = delete;

private:
  std::filesystem::path folder, lock;
  int descriptor = -1;
  bool created_folder = false, success = false;
};

/// The cached body in @p file if its input hash is @p hash; an unusable or stale file is reported.
bool load_if_up_to_date(const std::string &file, const std::string &hash, reduction::ReducedBody &body,
                        std::ostream &log)
{
  if (!std::filesystem::exists(file)) return false;
  try
    {
      // Checks every shape and value, the physical plausibility and the content checksum, also
      // of a cached file: a damaged one is reduced again (the log says why), never used.
      auto existing = read_reduced_body(file);
      if (existing.input_hash == hash)
        {
          body = std::move(existing);
          return true;
        }
      log << "  inputs changed since " << file << " was written (hash " << existing.input_hash << "): recomputing\n";
    }
  catch (const InputError &e)
    {
      log << "  the existing " << file << " is unusable (" << e.message() << "): recomputing\n";
    }
  return false;
}

/// Largest relative difference of the reduced frequencies from the full model's, as JSON.
JsonObject check_against_full_model(const fem::BodyModel &model, const reduction::ReductionSettings &settings,
                                    const std::vector<double> &reduced, std::ostream &log)
{
  dealii::Timer timer;
  const auto full = reduction::full_model_frequencies_hz(model, settings, settings.n_check_modes);
  const double seconds = timer.wall_time();
  double worst = 0;
  for (unsigned int k = 0; k < full.size() && k < reduced.size(); ++k)
    worst = std::max(worst, std::abs(reduced[k] - full[k]) / std::abs(full[k]));
  log << "  check against the full model: " << full.size() << " lowest frequencies, largest relative difference "
      << std::setprecision(3) << worst << " (full eigen solve " << seconds << " s)\n";
  JsonObject check;
  check.add("modes", static_cast<unsigned int>(full.size()))
    .add("max_relative_frequency_difference", worst)
    .add("full_model_frequencies_Hz", full)
    .add("full_model_eigen_solve_wall_time_s", seconds);
  return check;
}
} // namespace

ObtainedBody cached_or_reduced_body(const BodyScene &scene, const std::string &file, std::ostream &log,
                                    TimerOutput &timer, const std::function<void()> &before_reduction)
{
  ObtainedBody result;
  // Supports change the physics and default to free: the log says what each arm has.
  for (std::size_t a = 0; a < scene.body.arms.size(); ++a)
    log << "  arm " << scene.body.arm_names[a] << " supports: " << scene.body.arms[a].supports_text() << "\n";
  // Under MPI (a distributed reduction, reduction/component_modes.cc) the first process looks
  // the body up, locks and writes it; all take part in reducing it.
  const MPI_Comm communicator = base::fe_communicator();
  const bool first = is_first_process();
  const bool several = base::fe_processes() > 1;
  std::optional<CacheLock> lock;
  if (first) lock.emplace(file, log);
  {
    TimerOutput::Scope t(timer, "load cached reduced body");
    result.from_cache = first && load_if_up_to_date(file, scene.input_hash, result.body, log);
    // The other processes take part in reducing only (their caller, reduce_command, returns):
    // they do not read the file, which may be on the first process' machine alone.
    if (several) result.from_cache = dealii::Utilities::MPI::broadcast(communicator, result.from_cache, 0);
  }
  if (result.from_cache)
    {
      log << "  reduced body is up to date: loaded " << file << " (same input hash), nothing recomputed\n";
      if (lock) lock->obtained();
      return result;
    }
  if (before_reduction) before_reduction();
  try
    {
      std::unique_ptr<fem::BodyModel> model;
      {
        TimerOutput::Scope t(timer, "assemble body (K, M, ties)");
        model = std::make_unique<fem::BodyModel>(scene.body, communicator);
      }
      log << "  body: " << model->n_full_dofs() << " dofs, " << model->n_dofs() << " after ties and supports ("
          << (model->is_supported() ? "supported" : "free") << ")\n";
      const auto basis = reduction::reduce(*model, scene.reduction, &timer);
      if (basis.factor_bytes > 0)
        {
          std::ostringstream line; // its precision stays here, not on the log
          line.precision(3);
          line << "  factorisation: about " << basis.factor_bytes / 1073741824.0 << " GiB per process (estimated before it was made"
               << (several ? ", on the process that holds most" : "") << "), on top of "
               << basis.held_before_factor_bytes / 1073741824.0 << " GiB held then (the body model and its matrices)\n";
          log << line.str();
        }
      {
        TimerOutput::Scope t(timer, "invariants, mode fields, drawing");
        result.body = reduction::make_reduced_body(*model, basis, scene.reduction.method_name());
      }
      if (scene.reduction.n_check_modes > 0)
        {
          TimerOutput::Scope t(timer, "check against the full model");
          result.check = check_against_full_model(*model, scene.reduction, basis.frequencies_hz(), log);
          result.checked = true;
        }
    }
  catch (const InputError &e)
    {
      throw e.file().empty() ? e.in_file(scene.file) : e;
    }
  result.body.input_hash = scene.input_hash;
  result.body.source = scene.file;
  // The checks every read makes (reduction/plausibility.h), made once more before writing: a
  // body the reader would refuse is never written, nor used. Valid input that reduces to an
  // implausible body is a failure of the reduction, not of the input.
  try
    {
      reduction::check_physical_plausibility(result.body);
    }
  catch (const std::runtime_error &e)
    {
      throw SolverError(scene.file + ": the reduction gave a physically implausible body: " + e.what() +
                        "; nothing written (please report this scene)");
    }
  if (!first) return result;
  TimerOutput::Scope t(timer, "write reduced body");
  if (const auto folder = std::filesystem::path(file).parent_path(); !folder.empty())
    OutputFolder(folder.string()).create();
  write_reduced_body(result.body, file);
  lock->obtained();
  return result;
}
} // namespace flextrack::io
