// flextrack sweep: a parameter study (io/study.h, doc/sweep.md). Every case is the study's scene
// run with the case's --set entries into a folder of its own, OUT/case_NNNN/ (its log in log.txt
// and its record in case.json); sweep.csv gathers one row per case.
//
// How cases run. Starting the program costs about 0.5 s (the dynamic linker resolving deal.II's
// libraries), more than many cases take, so no case starts a program:
//  - on one machine (`-j N`) this process forks N workers, each runs cases one after another
//    as `flextrack run` would, the next one handed out by this process over a pipe. A case that
//    crashes is one row ("crashed"), not the end of the study; a new worker replaces its own.
//  - under `mpirun -np N` every process runs cases itself, one after another, taking the next one
//    from a counter on the first process (MPI_Fetch_and_op on a one-sided window: a dynamic
//    queue, so a long case does not keep the others idle). A flexible body is then reduced on
//    the process's own communicator (base::use_own_process_for_fe).
// A reduced body that several cases share is reduced once: the cache takes a lock while it
// reduces, and the other cases wait for it and load the file (io/reduced_body_cache.h).
//
// Restart: a case whose folder holds a case.json with the case's key (the scene's text and its
// entries) is done and is not run again; an interrupted or killed case left none. Bad input in
// the study or in any case's entries is refused before the first case runs.
#include <app/commands.h>
#include <app/exit_status.h>
#include <base/input_error.h>
#include <base/interrupt.h>
#include <base/mpi_session.h>
#include <base/text.h>
#include <io/body_scene.h>
#include <io/gnuplot.h>
#include <io/json.h>
#include <io/multibody_scene.h>
#include <io/output_folder.h>
#include <io/study.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/timer.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <fcntl.h>
#include <sched.h>
#include <mpi.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <limits>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace flextrack::app
{
namespace fs = std::filesystem;

namespace
{
/// What became of one case (case.json, a row of sweep.csv).
struct CaseRecord
{
  std::string status;  ///< completed, failed (solver), bad input, crashed, interrupted
  int exit_status = 0; ///< as `flextrack run` would have exited
  std::string message; ///< the error line, "" when completed
  double cpu_time_s = 0, wall_time_s = 0;
  std::vector<std::string> collected;
};

std::string status_of_exit(const int code)
{
  switch (code)
    {
      case 0: return "completed";
      case 2: return "bad input";
      case 3: return "failed";
      case 4: return "internal error";
      case 128 + SIGINT:
      case 128 + SIGTERM: return "interrupted"; // run again when the study is
      default: return "crashed";
    }
}

/// Runs case @p c in this process as `flextrack run SCENE -o FOLDER --set ...` would; returns the
/// exit status and sets @p message to the error line (main.cc's, through run_guarded).
int run_case_here(const io::Study &study, const io::StudyCase &c, std::string &message)
{
  const auto outcome = run_guarded([&] {
    Options options;
    options.file = study.scene;
    options.output_directory = c.folder;
    options.overrides = c.set;
    return run_command(options, io::SceneFile::read(study.scene, c.set));
  });
  message = outcome.message;
  return outcome.status;
}

/// Sends this process's output (C and C++, and that of the libraries) to @p file while it lives.
class OutputToFile
{
public:
  explicit OutputToFile(const std::string &file)
  {
    std::cout.flush();
    std::fflush(nullptr);
    const int fd = ::open(file.c_str(), O_CREAT | O_WRONLY | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return;
    saved_out = ::dup(STDOUT_FILENO);
    saved_err = ::dup(STDERR_FILENO);
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
  }
  ~OutputToFile()
  {
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    if (saved_out < 0) return;
    ::dup2(saved_out, STDOUT_FILENO);
    ::dup2(saved_err, STDERR_FILENO);
    ::close(saved_out);
    ::close(saved_err);
  }
  OutputToFile(const OutputToFile &) = delete;
  OutputToFile &operator=(const OutputToFile &) = delete;

private:
  int saved_out = -1, saved_err = -1;
};

/// CPU time (user + system) of this process so far [s].
double process_cpu_seconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double seconds_since(const std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A value for a CSV cell: quoted when it holds a comma, a quote or a line break.
std::string csv_cell(const std::string &text)
{
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' || c == '\r' ? ' ' : c);
  return quoted + "\"";
}

/// What a worker process says of a case it ran.
struct CaseReport
{
  int code = 0;
  double cpu_s = 0, run_wall_s = 0;
  std::string message;
};

bool read_exactly(const int fd, void *data, const std::size_t size)
{
  auto *bytes = static_cast<char *>(data);
  for (std::size_t done = 0; done < size;)
    {
      const ssize_t n = ::read(fd, bytes + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      done += n;
    }
  return true;
}

bool write_exactly(const int fd, const void *data, const std::size_t size)
{
  const auto *bytes = static_cast<const char *>(data);
  for (std::size_t done = 0; done < size;)
    {
      const ssize_t n = ::write(fd, bytes + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      done += n;
    }
  return true;
}

bool read_report(const int fd, CaseReport &r)
{
  std::uint64_t length = 0;
  if (!read_exactly(fd, &r.code, sizeof r.code) || !read_exactly(fd, &r.cpu_s, sizeof r.cpu_s) ||
      !read_exactly(fd, &r.run_wall_s, sizeof r.run_wall_s) || !read_exactly(fd, &length, sizeof length) || length > (1u << 20))
    return false;
  r.message.assign(length, ' ');
  return read_exactly(fd, r.message.data(), length);
}

bool write_report(const int fd, const CaseReport &r)
{
  const std::uint64_t length = r.message.size();
  return write_exactly(fd, &r.code, sizeof r.code) && write_exactly(fd, &r.cpu_s, sizeof r.cpu_s) &&
         write_exactly(fd, &r.run_wall_s, sizeof r.run_wall_s) && write_exactly(fd, &length, sizeof length) &&
         write_exactly(fd, r.message.data(), length);
}

class Sweep
{
public:
  Sweep(const Options &options, const io::SceneFile &file)
    : study(io::read_study(file)),
      folder(io::OutputFolder::choose(options.output_directory, study.output_directory, options.file))
  {
    io::SceneFile scene;
    try
      {
        scene = io::SceneFile::read(study.scene);
      }
    catch (const InputError &e)
      {
        throw InputError("Study/Scene", e.what(), study.file);
      }
    if (scene.model != "multibody")
      throw InputError("Study/Scene", "'" + study.scene + "' is a '" + scene.model + "' scene; a study runs a multibody scene", study.file);
    cases = study.cases(scene.text, folder);
    records.resize(cases.size());
    done.assign(cases.size(), false);
  }

  /// Refuses (InputError, naming the case) an entry of any case that its scene or body scene does
  /// not declare or whose value does not match; only parameter files are read (no process of a
  /// sweep has started threads before its cases are forked). Checks the cases @p first,
  /// first + @p stride, ... (the share of one MPI process).
  void check_every_case(const unsigned int first = 0, const unsigned int stride = 1) const
  {
    std::set<std::string> bodies_checked;
    for (std::size_t i = first; i < cases.size(); i += stride)
      try
        {
          const auto &c = cases[i];
          const auto scene = io::SceneFile::read(study.scene, c.set);
          dealii::ParameterHandler prm;
          const auto names = multibody::SceneNames::parse_name_lists(*scene.lists);
          io::declare_multibody_scene(prm, names);
          scene.parse(prm, false);
          for (const auto &o : c.set)
            {
              if (o.scope.empty()) continue;
              std::string signature = o.scope;
              const std::string body = o.scope.substr(5); // "Body NAME"
              for (const auto &own : scene.overrides_of(body)) signature += "\n" + own.text();
              if (!bodies_checked.insert(signature).second) continue;
              if (std::find(names.bodies.begin(), names.bodies.end(), body) == names.bodies.end())
                throw InputError("--set", "'" + o.text() + "': the scene has no body '" + body + "'; its bodies: " +
                                            base::joined(names.bodies));
              prm.enter_subsection(o.scope);
              const std::string body_scene = base::trim(prm.get("Body scene"));
              prm.leave_subsection();
              if (body_scene.empty())
                throw InputError("--set", "'" + o.text() + "': body '" + body + "' has no Body scene to set entries in");
              const auto body_file = io::SceneFile::read(
                fs::path(body_scene).is_absolute() ? body_scene : (fs::path(scene.directory) / body_scene).string(), scene.overrides_of(body));
              dealii::ParameterHandler body_prm;
              io::parse_body_scene_entries(body_file, body_prm);
            }
        }
      catch (const InputError &e)
        {
          throw InputError("", "case " + std::to_string(cases[i].number) + " (" + describe(cases[i]) + "): " + e.what(), study.file);
        }
      catch (const dealii::ExceptionBase &e) // deal.II's own refusal of a name: still the case's input
        {
          throw InputError("", "case " + std::to_string(cases[i].number) + " (" + describe(cases[i]) + "): " +
                                 base::printable_excerpt(base::trim(e.what()), 300), study.file);
        }
  }

  /// Marks the cases that a previous run of this study finished (case.json with the same key).
  unsigned int find_finished_cases()
  {
    unsigned int n = 0;
    for (std::size_t i = 0; i < cases.size(); ++i)
      if (read_record(cases[i], records[i]))
        {
          done[i] = true;
          ++n;
        }
    return n;
  }

  std::vector<std::size_t> pending() const
  {
    std::vector<std::size_t> list;
    for (std::size_t i = 0; i < cases.size(); ++i)
      if (!done[i]) list.push_back(i);
    return list;
  }

  /// -j N: N forked worker processes run the cases, each one after another in its own process
  /// (warm: a worker's second case no longer pays for the first use of the libraries, which made
  /// a case in a fresh process 1.6 times as slow), this process hands out the next case to the
  /// worker that finishes one. A worker that dies takes only its case with it ("crashed"); a new
  /// one takes its place. Returns the signal that stopped the study (SIGINT, SIGTERM), 0 if none.
  int run_forked(const std::vector<std::size_t> &list, const unsigned int jobs)
  {
    struct Worker
    {
      pid_t pid = -1;
      int to = -1, from = -1;     // pipes to and from the worker
      std::size_t index = 0;      // the case it runs
      bool busy = false;
      bool dead = false;          // ended before it took its case: start another
      double cpu_reported = 0;    // CPU time of its finished cases [s]
      std::chrono::steady_clock::time_point start;
    };
    std::vector<Worker> workers(std::min<std::size_t>(jobs, list.size()));
    std::size_t next = 0, started = 0;
    bool stopping = false;
    const auto give_next = [&](Worker &w) {
      std::uint64_t message = std::numeric_limits<std::uint64_t>::max(); // stop
      w.busy = !stopping && next < list.size();
      if (w.busy)
        {
          w.index = list[next++];
          message = w.index;
          w.start = std::chrono::steady_clock::now();
        }
      if (!write_exactly(w.to, &message, sizeof message) && w.busy) // it died between cases: the case goes back
        {
          --next;
          w.busy = false;
          w.dead = true;
        }
    };
    const auto start_worker = [&](Worker &w) {
      if (++started > 2 * list.size() + 16) throw std::runtime_error("sweep: the worker processes keep dying before their first case");
      int down[2], up[2];
      if (pipe2(down, O_CLOEXEC) != 0) throw std::runtime_error("sweep: cannot create a pipe");
      if (pipe2(up, O_CLOEXEC) != 0)
        {
          ::close(down[0]);
          ::close(down[1]);
          throw std::runtime_error("sweep: cannot create a pipe");
        }
      std::cout.flush();
      std::fflush(nullptr);
      const pid_t pid = fork();
      if (pid < 0) throw std::runtime_error("sweep: fork failed");
      if (pid == 0)
        {
          ::close(down[1]);
          ::close(up[0]);
          work_on_cases(down[0], up[1]);
        }
      ::close(down[0]);
      ::close(up[1]);
      w = Worker();
      w.pid = pid;
      w.to = down[1];
      w.from = up[0];
      give_next(w);
    };
    std::signal(SIGPIPE, SIG_IGN); // a worker that died: its pipe says so, not a signal
    // A worker that reduces a body starts MPI as a singleton, and ends without MPI_Finalize
    // (_Exit): their session files go to one folder of this study's, removed at the end.
    const std::string mpi_folder = base::prepare_singleton_mpi();
    base::watch_interrupts();
    const auto replace_dead_workers = [&] {
      for (auto &w : workers)
        if (w.dead)
          {
            if (w.pid > 0) // never kill(-1): that would be every process
              {
                kill(w.pid, SIGKILL);
                waitpid(w.pid, nullptr, 0);
              }
            ::close(w.to);
            ::close(w.from);
            w.dead = false;
            w.pid = -1;
            if (!stopping && next < list.size()) start_worker(w);
          }
    };
    for (auto &w : workers) start_worker(w);
    replace_dead_workers();
    bool forwarded = false;
    while (std::any_of(workers.begin(), workers.end(), [](const Worker &w) { return w.busy; }))
      {
        if (const int signal = base::interrupted(); signal && !forwarded)
          {
            stopping = forwarded = true; // once: a second signal would end a case without its results
            for (const auto &w : workers)
              if (w.busy) kill(w.pid, signal);
          }
        std::vector<pollfd> watched;
        for (const auto &w : workers)
          if (w.busy) watched.push_back({w.from, POLLIN, 0});
        if (poll(watched.data(), watched.size(), 200) <= 0) continue; // a signal, or nothing yet
        for (auto &w : workers)
          {
            const auto ready = std::find_if(watched.begin(), watched.end(), [&](const pollfd &p) { return p.fd == w.from; });
            if (!w.busy || ready == watched.end() || ready->revents == 0) continue;
            const double wall = seconds_since(w.start);
            CaseReport report;
            if (read_report(w.from, report))
              {
                machinery_seconds += std::max(0.0, wall - report.run_wall_s); // handing out, reporting
                w.cpu_reported += report.cpu_s;
                finish_case(w.index, report.code, report.message, report.cpu_s, wall, "");
                if (report.code > 128) stopping = true; // interrupted: the study stops
                give_next(w);
              }
            else // the worker died with its case (or said something unreadable: it is ended)
              {
                int status = 0;
                rusage usage{};
                if (waitpid(w.pid, nullptr, WNOHANG) == 0) kill(w.pid, SIGKILL);
                wait4(w.pid, &status, 0, &usage);
                ::close(w.to);
                ::close(w.from);
                const double cpu = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec + usage.ru_stime.tv_sec +
                                   1e-6 * usage.ru_stime.tv_usec - w.cpu_reported;
                const int code = WIFSIGNALED(status) ? 128 + WTERMSIG(status) : WIFEXITED(status) ? WEXITSTATUS(status) : 4;
                finish_case(w.index, code == 0 ? 4 : code,
                            "the case's process ended " + (WIFSIGNALED(status) ? "by signal " + std::to_string(WTERMSIG(status))
                                                                                : "with exit status " + std::to_string(code)) +
                              " (log: " + cases[w.index].folder + "/log.txt)",
                            cpu, wall, "");
                w.busy = false;
                w.pid = -1;
                if (!stopping && next < list.size()) start_worker(w);
              }
            replace_dead_workers();
            const auto written = std::chrono::steady_clock::now();
            write_table(false); // sweep.csv grows as the cases end
            machinery_seconds += seconds_since(written);
          }
      }
    for (auto &w : workers)
      if (w.pid > 0)
        {
          ::close(w.to); // a worker that was told to stop ends; one still reading ends at EOF
          ::close(w.from);
          waitpid(w.pid, nullptr, 0);
        }
    base::remove_mpi_session_folder(mpi_folder);
    const int signal = base::interrupted();
    base::stop_watching_interrupts();
    std::signal(SIGPIPE, SIG_DFL);
    return signal;
  }

  /// mpirun: this process runs cases in turn, the next one from the shared counter. Returns the
  /// signal that stopped a case here (its exit status - 128), 0 if none.
  int run_on_mpi_process(const std::vector<std::size_t> &list)
  {
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    // The counter of the cases taken, on the first process. One process needs no window (and
    // Open MPI 4.1 refuses one there: "MPI_ERR_WIN: invalid window"); where a window cannot be
    // made the processes take every size-th case instead (said in the log).
    // MPI_Win_allocate, not MPI_Win_create: the library then places the counter where every
    // process can update it without the first process's help (shared memory on one node, network
    // atomics between nodes); with MPI_Win_create (Open MPI's pt2pt/rdma path) a process waited
    // for the first one to finish its case: 2 processes were 1.43 times as fast as 1, not 1.9.
    long *counter = nullptr;
    MPI_Win window = MPI_WIN_NULL;
    bool shared_counter = false;
    if (size > 1)
      {
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
        int made = MPI_Win_allocate(rank == 0 ? sizeof(long) : 0, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD, &counter, &window);
        MPI_Allreduce(MPI_IN_PLACE, &made, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
        shared_counter = made == MPI_SUCCESS;
        if (shared_counter && rank == 0)
          {
            MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, window);
            *counter = 0;
            MPI_Win_unlock(0, window);
          }
        MPI_Barrier(MPI_COMM_WORLD);
        if (!shared_counter && rank == 0)
          std::cout << "  no one-sided MPI window here: process k runs cases k, k + " << size << ", ... (no dynamic queue)" << std::endl;
      }
    const long one = 1;
    long own_next = rank;
    int stopped_by = 0;
    const std::string who = " (process " + std::to_string(rank) + " of " + std::to_string(size) + ")";
    while (true)
      {
        long taken = 0;
        if (shared_counter)
          {
            MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window);
            MPI_Fetch_and_op(&one, &taken, MPI_LONG, 0, 0, MPI_SUM, window);
            MPI_Win_unlock(0, window);
          }
        else
          {
            taken = own_next;
            own_next += size;
          }
        if (taken >= static_cast<long>(list.size())) break;
        const std::size_t i = list[taken];
        int code = 0;
        try
          {
            code = run_and_record_here(i, who);
          }
        catch (const std::exception &e) // e.g. case.json on a full disk: the others would wait forever
          {
            std::cerr << "flextrack: sweep: process " << rank << ": " << e.what() << "; stopping every process" << std::endl;
            MPI_Abort(MPI_COMM_WORLD, 4);
          }
        if (code > 128) // interrupted: mpirun signalled the other processes too
          {
            stopped_by = code - 128;
            break;
          }
      }
    MPI_Barrier(MPI_COMM_WORLD);
    if (shared_counter) MPI_Win_free(&window);
    // The first process writes the table from every case's record.
    if (rank == 0) find_finished_cases();
    MPI_Allreduce(MPI_IN_PLACE, &stopped_by, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return stopped_by;
  }

  /// mpirun: runs case @p i in this process and records it; returns its exit status.
  int run_and_record_here(const std::size_t i, const std::string &who)
  {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    std::string message;
    int code = 0;
    {
      std::error_code ec;
      fs::remove_all(cases[i].folder, ec); // a previous run's results are not this case's
      fs::create_directories(cases[i].folder, ec);
      OutputToFile log(cases[i].folder + "/log.txt");
      code = run_case_here(study, cases[i], message);
    }
    finish_case(i, code, message, process_cpu_seconds() - cpu_start, seconds_since(start), who);
    return code;
  }

  /// sweep.csv (atomically); @p with_differences: with the quantities compared with the
  /// reference case (at the end: each reads two probes.csv files).
  void write_table(const bool with_differences) const
  {
    std::ostringstream csv;
    csv << "case";
    for (const auto &p : study.parameters) csv << "," << csv_cell(p.name);
    for (const auto &q : study.quantities) csv << "," << csv_cell(q.text);
    csv << ",status,exit_status,cpu_time_s,wall_time_s,message\n";
    std::string reference_folder = study.reference_case ? cases[study.reference_case - 1].folder : "";
    const bool reference_done = with_differences && study.reference_case && done[study.reference_case - 1];
    for (std::size_t i = 0; i < cases.size(); ++i)
      {
        if (!done[i]) continue;
        const auto &r = records[i];
        csv << cases[i].number;
        for (const auto &v : cases[i].values) csv << "," << csv_cell(v);
        for (std::size_t k = 0; k < study.quantities.size(); ++k)
          {
            const auto &q = study.quantities[k];
            const std::string value = q.kind != io::Quantity::Kind::reference ? r.collected[k]
                                      : reference_done && r.status == "completed"
                                        ? io::probe_difference(q.path, cases[i].folder, reference_folder)
                                        : "";
            csv << "," << csv_cell(value);
          }
        csv << "," << r.status << "," << r.exit_status << "," << base::number_text(r.cpu_time_s) << ","
            << base::number_text(r.wall_time_s) << "," << csv_cell(r.message) << "\n";
      }
    io::write_atomically(folder + "/sweep.csv", [&](const std::string &temporary) {
      std::ofstream out(temporary);
      out << csv.str();
      if (!out.flush()) throw InputError("Study/Output directory", "cannot write '" + folder + "/sweep.csv'");
    });
  }

  /// sweep.png: the first numeric quantity against the parameter (one parameter), or as the
  /// colour of a map over two; none for more. Returns what was drawn ("" if nothing).
  std::string draw_plot() const
  {
    if (study.quantities.empty() || study.parameters.size() > 2) return "";
    const unsigned int n_parameters = study.parameters.size();
    std::vector<std::string> names;
    for (const auto &q : study.quantities) names.push_back(q.text);
    std::vector<std::string> parameter_names;
    for (const auto &p : study.parameters) parameter_names.push_back(p.name);
    io::write_atomically(folder + "/sweep.gp", [&](const std::string &temporary) {
      std::ofstream(temporary) << io::sweep_plot_script(study.file, parameter_names, names);
    });
    const auto plot = io::draw_png(folder, "sweep.gp", "sweep.png");
    if (!plot.drawn)
      {
        std::cout << "  warning: no sweep.png: " << plot.problem << " (sweep.gp draws it)\n";
        return "";
      }
    return n_parameters == 1 ? "sweep.png" : "sweep.png (map)";
  }

  std::size_t size() const { return cases.size(); }
  const std::string &output_folder() const { return folder; }
  const io::Study &the_study() const { return study; }
  /// Counts of the finished cases by status.
  std::map<std::string, unsigned int> statuses() const
  {
    std::map<std::string, unsigned int> count;
    for (std::size_t i = 0; i < cases.size(); ++i)
      if (done[i]) ++count[records[i].status];
    return count;
  }
private:
  io::Study study;
  std::string folder;
  std::vector<io::StudyCase> cases;
  std::vector<CaseRecord> records;
  std::vector<bool> done;

  /// A worker process (run_forked): runs the case whose number it reads from @p from_parent,
  /// reports it on @p to_parent, until told to stop or its parent is gone.
  [[noreturn]] void work_on_cases(const int from_parent, const int to_parent) const
  {
    prctl(PR_SET_PDEATHSIG, SIGTERM); // the study killed: its cases stop too
    // Out of the terminal's process group: Ctrl-C reaches the study alone, which passes it on
    // once (a second signal would end a case at once, without its results).
    setpgid(0, 0);
    base::stop_watching_interrupts();
    std::signal(SIGPIPE, SIG_DFL);
    for (std::uint64_t i = 0; read_exactly(from_parent, &i, sizeof i) && i < cases.size();)
      {
        CaseReport report;
        const auto start = std::chrono::steady_clock::now();
        const double cpu_start = process_cpu_seconds();
        {
          std::error_code ec;
          fs::remove_all(cases[i].folder, ec); // a previous run's results are not this case's
          fs::create_directories(cases[i].folder, ec);
          OutputToFile log(cases[i].folder + "/log.txt");
          report.code = run_case_here(study, cases[i], report.message);
        }
        report.cpu_s = process_cpu_seconds() - cpu_start;
        report.run_wall_s = seconds_since(start);
        if (!write_report(to_parent, report)) break;
      }
    std::_Exit(0); // no exit handlers: they belong to the parent
  }

public:
  /// Wall time of the sweep's own work on the cases run here: forking and reaping them,
  /// collecting their quantities, their records and sweep.csv [s].
  double machinery_seconds = 0;
  unsigned int cases_run = 0;

private:
  std::string describe(const io::StudyCase &c) const
  {
    std::vector<std::string> items;
    for (std::size_t j = 0; j < study.parameters.size(); ++j) items.push_back(study.parameters[j].name + " = " + c.values[j]);
    return base::joined(items, ", ");
  }

  /// Collects the case's quantities, writes its case.json and says it in the log.
  void finish_case(const std::size_t i, const int code, const std::string &message, const double cpu, const double wall,
                   const std::string &who)
  {
    const auto start = std::chrono::steady_clock::now();
    struct AddTime // the time of this function is the sweep's, however it returns
    {
      double &sum;
      std::chrono::steady_clock::time_point start;
      ~AddTime() { sum += seconds_since(start); }
    } add_time{machinery_seconds, start};
    ++cases_run;
    CaseRecord r;
    r.exit_status = code;
    r.status = status_of_exit(code);
    r.message = message;
    r.cpu_time_s = cpu;
    r.wall_time_s = wall;
    // Only a completed case has its quantities; a failed one's partial rows would mislead.
    r.collected = r.status == "completed" ? io::collect_quantities(study.quantities, cases[i].folder)
                                          : std::vector<std::string>(study.quantities.size());
    std::cout << "  case " << cases[i].number << "/" << cases.size() << who << ": " << r.status << ", "
              << std::setprecision(3) << cpu << " s CPU (" << describe(cases[i]) << ")"
              << (message.empty() ? "" : ": " + base::printable_excerpt(message, 300)) << std::endl;
    if (r.status == "interrupted") return; // run again on restart
    io::JsonObject j;
    j.add("case", cases[i].number).add("key", cases[i].key).add("status", r.status).add("exit_status", code)
      .add("message", message).add("cpu_time_s", cpu).add("wall_time_s", wall)
      .add("set", io::override_texts(cases[i].set)).add("collected", r.collected);
    io::write_atomically(cases[i].folder + "/case.json", [&](const std::string &temporary) { std::ofstream(temporary) << j.str() << "\n"; });
    records[i] = r;
    done[i] = true;
  }

  bool read_record(const io::StudyCase &c, CaseRecord &r) const
  {
    try
      {
        boost::property_tree::ptree tree;
        boost::property_tree::read_json(c.folder + "/case.json", tree);
        if (tree.get<std::string>("key") != c.key) return false;
        r.status = tree.get<std::string>("status");
        // Numbers through their text: boost's get<int> and get<double> make GCC 12 warn
        // (-Wmaybe-uninitialized inside boost::optional).
        r.exit_status = std::stoi(tree.get<std::string>("exit_status"));
        r.message = tree.get<std::string>("message");
        r.cpu_time_s = std::stod(tree.get<std::string>("cpu_time_s"));
        r.wall_time_s = std::stod(tree.get<std::string>("wall_time_s"));
        // Collected again from the case's results: the study's quantities may have changed.
        r.collected = r.status == "completed" ? io::collect_quantities(study.quantities, c.folder)
                                              : std::vector<std::string>(study.quantities.size());
        return true;
      }
    catch (const std::exception &)
      {
        return false; // none, or unreadable (a crash while it was renamed cannot leave half a file)
      }
  }
};
} // namespace

int sweep_command(const Options &options, const io::SceneFile &file)
{
  const auto start = std::chrono::steady_clock::now();
  const bool on_mpi = base::started_by_mpirun();
  if (on_mpi && options.jobs > 0)
    throw InputError("-j", "runs cases in processes of one machine; under mpirun every MPI process runs cases: give one, not both");
  int rank = 0, size = 1;
  if (on_mpi)
    {
      // Every process reports its own cases (start_mpi silences all but the first by default).
      auto *buffer = std::cout.rdbuf();
      start_mpi_for_reduction();
      std::cout.rdbuf(buffer);
      base::use_own_process_for_fe();
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      MPI_Comm_size(MPI_COMM_WORLD, &size);
    }
  // Not given: as many cases at once as this process may use cores (a study is many independent
  // runs; each uses one core), said in the log.
  unsigned int jobs = options.jobs;
  std::string jobs_text = std::to_string(jobs) + " at once (-j)";
  if (jobs == 0)
    {
      cpu_set_t cores;
      CPU_ZERO(&cores);
      jobs = sched_getaffinity(0, sizeof cores, &cores) == 0 ? std::max(1, CPU_COUNT(&cores)) : 1;
      jobs_text = std::to_string(jobs) + " at once (chosen: the cores this process may use; -j N sets it)";
    }
  Sweep sweep(options, file);
  const auto &study = sweep.the_study();
  if (rank == 0)
    std::cout << "flextrack sweep: " << options.file << "\n  scene " << study.scene << ", " << study.design << " design, "
              << sweep.size() << " cases, " << (on_mpi ? std::to_string(size) + " MPI processes" : jobs_text)
              << "; results in " << sweep.output_folder() << "/" << std::endl;
  if (!on_mpi)
    sweep.check_every_case();
  else
    {
      // Each process checks its share of the cases; the first bad case of all is reported (by the
      // process that found it), and every process ends with exit status 2.
      int bad = std::numeric_limits<int>::max();
      std::optional<InputError> found;
      try
        {
          sweep.check_every_case(rank, size);
        }
      catch (const InputError &e)
        {
          found = e;
          bad = std::stoi(e.message().substr(5)); // "case N (...": its number
        }
      int first_bad = bad;
      MPI_Allreduce(&bad, &first_bad, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
      if (found && bad == first_bad) throw *found;
      if (first_bad != std::numeric_limits<int>::max()) return 2; // reported by another process
    }
  const unsigned int finished = sweep.find_finished_cases();
  const auto list = sweep.pending();
  if (rank == 0 && finished > 0)
    std::cout << "  " << finished << " cases finished by an earlier run of this study (case.json, same entries): " << list.size()
              << " to run" << std::endl;
  if (on_mpi) MPI_Barrier(MPI_COMM_WORLD); // every process has seen which cases are done
  const int signal = on_mpi ? sweep.run_on_mpi_process(list) : sweep.run_forked(list, jobs);
  if (rank != 0) return signal ? 128 + signal : 0;
  io::OutputFolder(sweep.output_folder()).create();
  sweep.write_table(true);
  const std::string plot = signal ? "" : sweep.draw_plot();
  const double wall = seconds_since(start);
  std::vector<std::string> counts;
  unsigned int n_done = 0;
  for (const auto &[status, n] : sweep.statuses())
    {
      counts.push_back(std::to_string(n) + " " + status);
      n_done += n;
    }
  std::cout << "  " << n_done << " of " << sweep.size() << " cases: " << base::joined(counts, ", ") << "; study wall time "
            << std::setprecision(3) << wall << " s";
  if (sweep.cases_run > 0)
    std::cout << "\n  the sweep's own work per case: " << std::setprecision(2) << 1e3 * sweep.machinery_seconds / sweep.cases_run
              << " ms (fork, collecting, case.json, sweep.csv" << (on_mpi ? ", on the first process" : "") << ")";
  std::cout << "\n  results in " << sweep.output_folder() << "/ (sweep.csv" << (plot.empty() ? "" : ", " + plot)
            << ", case_NNNN/)" << std::endl;
  if (n_done < sweep.size())
    throw base::Interrupted(signal ? signal : SIGTERM, "the study stopped with " + std::to_string(sweep.size() - n_done) +
                                      " cases to run; run it again to run only those");
  return 0;
}
} // namespace flextrack::app
