// flextrack sweep: a parameter study (io/study.h, doc/sweep.md). Every case is the study's scene
// run with the case's --set entries into a folder of its own, OUT/case_NNNN/ (its log in log.txt
// and its record in case.json); sweep.csv gathers one row per case.
//
// How cases run. Starting the program costs about 0.5 s (the dynamic linker resolving deal.II's
// libraries), more than many cases take, so no case starts a program:
//  - on one machine (`-j N`) this process forks a child per case, at most N at once; the child
//    runs the case as `flextrack run` would and ends. A case that crashes is one row ("crashed"),
//    not the end of the study, and its CPU time is the child's (wait4).
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
#include <base/input_error.h>
#include <base/interrupt.h>
#include <base/mpi_session.h>
#include <base/solver_error.h>
#include <base/text.h>
#include <fem/body.h>
#include <fem/load_case.h>
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
#include <mpi.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

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
      default: return code > 128 ? "interrupted" : "crashed";
    }
}

/// Runs case @p c in this process as `flextrack run SCENE -o FOLDER --set ...` would; returns the
/// exit status and sets @p message to the error line (main.cc's rules).
int run_case_here(const io::Study &study, const io::StudyCase &c, std::string &message)
{
  try
    {
      Options options;
      options.file = study.scene;
      options.output_directory = c.folder;
      options.overrides = c.set;
      const auto scene = io::SceneFile::read(study.scene, c.set);
      return run_command(options, scene);
    }
  catch (const InputError &e)
    {
      message = e.what();
      return 2;
    }
  catch (const base::Interrupted &e)
    {
      message = e.what();
      return 128 + e.signal();
    }
  catch (const SolverError &e)
    {
      message = e.what();
      return 3;
    }
  catch (const dealii::ExceptionBase &e)
    {
      std::ostringstream s;
      e.print_info(s);
      message = "internal error: " + base::trim(s.str());
      return 4;
    }
  catch (const std::exception &e)
    {
      message = std::string("internal error: ") + e.what();
      return 4;
    }
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
  /// sweep has started threads before its cases are forked).
  void check_every_case() const
  {
    std::set<std::string> bodies_checked;
    for (const auto &c : cases)
      try
        {
          const auto scene = io::SceneFile::read(study.scene, c.set);
          dealii::ParameterHandler prm;
          io::declare_multibody_scene(prm, multibody::SceneNames::parse_name_lists(*scene.lists));
          scene.parse(prm, false);
          for (const auto &o : c.set)
            {
              if (o.scope.empty()) continue;
              std::string signature = o.scope;
              const std::string body = o.scope.substr(5); // "Body NAME"
              for (const auto &own : scene.overrides_of(body)) signature += "\n" + own.text();
              if (!bodies_checked.insert(signature).second) continue;
              prm.enter_subsection(o.scope);
              const std::string body_scene = base::trim(prm.get("Body scene"));
              prm.leave_subsection();
              if (body_scene.empty())
                throw InputError("--set", "'" + o.text() + "': body '" + body + "' has no Body scene to set entries in");
              const auto body_file = io::SceneFile::read(
                fs::path(body_scene).is_absolute() ? body_scene : (fs::path(scene.directory) / body_scene).string(), scene.overrides_of(body));
              dealii::ParameterHandler body_prm;
              io::declare_body_scene(body_prm, fem::Body::parse_arm_list(*body_file.lists));
              fem::StaticSettings::declare_parameters(body_prm);
              fem::LoadCase::declare_parameters(body_prm, fem::StaticSettings::parse_load_case_list(*body_file.lists));
              body_file.parse(body_prm, false);
            }
        }
      catch (const InputError &e)
        {
          throw InputError("", "case " + std::to_string(c.number) + " (" + describe(c) + "): " + e.what(), study.file);
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

  /// -j N: a forked child per case, at most @p jobs at once. Returns the signal that stopped the
  /// study (SIGINT, SIGTERM), 0 if none.
  int run_forked(const std::vector<std::size_t> &list, const unsigned int jobs)
  {
    struct Running
    {
      std::size_t index;
      int pipe;
      std::chrono::steady_clock::time_point start;
    };
    std::map<pid_t, Running> running;
    std::size_t next = 0;
    bool forwarded = false;
    base::watch_interrupts();
    while (next < list.size() || !running.empty())
      {
        const int signal = base::interrupted();
        if (signal && !forwarded) // once: a second signal would end a case without its results
          for (const auto &r : running) kill(r.first, signal);
        forwarded = forwarded || signal;
        while (!signal && next < list.size() && running.size() < jobs)
          {
            const std::size_t i = list[next++];
            int channel[2];
            if (pipe2(channel, O_CLOEXEC) != 0) throw std::runtime_error("sweep: cannot create a pipe");
            std::cout.flush();
            std::fflush(nullptr);
            const pid_t pid = fork();
            if (pid < 0) throw std::runtime_error("sweep: fork failed");
            if (pid == 0)
              {
                ::close(channel[0]);
                prctl(PR_SET_PDEATHSIG, SIGTERM); // the study killed: its cases stop too
                base::stop_watching_interrupts();
                std::string message;
                int code = 0;
                {
                  std::error_code ec;
                  fs::create_directories(cases[i].folder, ec);
                  OutputToFile log(cases[i].folder + "/log.txt");
                  code = run_case_here(study, cases[i], message);
                }
                if (!message.empty() && ::write(channel[1], message.data(), message.size()) < 0) code = 4;
                std::_Exit(code); // no exit handlers: they belong to the parent (MPI, HDF5)
              }
            ::close(channel[1]);
            running[pid] = {i, channel[0], std::chrono::steady_clock::now()};
          }
        int status = 0;
        rusage usage{};
        const pid_t pid = wait4(-1, &status, WNOHANG, &usage);
        if (pid <= 0)
          {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            continue;
          }
        const auto r = running.at(pid);
        running.erase(pid);
        std::string message;
        char buffer[4096];
        for (ssize_t n; (n = ::read(r.pipe, buffer, sizeof buffer)) > 0;) message.append(buffer, n);
        ::close(r.pipe);
        const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        if (WIFSIGNALED(status) && message.empty())
          message = "the case's process ended by signal " + std::to_string(WTERMSIG(status)) + " (log: " + cases[r.index].folder + "/log.txt)";
        const double cpu = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec + usage.ru_stime.tv_sec + 1e-6 * usage.ru_stime.tv_usec;
        finish_case(r.index, code, message, cpu, seconds_since(r.start), "");
        write_table(false); // sweep.csv grows as the cases end
      }
    const int signal = base::interrupted();
    base::stop_watching_interrupts();
    return signal;
  }

  /// mpirun: this process runs cases in turn, the next one from the shared counter. Returns the
  /// signal that stopped a case here (its exit status - 128), 0 if none.
  int run_on_mpi_process(const std::vector<std::size_t> &list)
  {
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    long counter = 0;
    MPI_Win window;
    MPI_Win_create(rank == 0 ? &counter : nullptr, rank == 0 ? sizeof counter : 0, sizeof counter, MPI_INFO_NULL,
                   MPI_COMM_WORLD, &window);
    const long one = 1;
    int stopped_by = 0;
    const std::string who = " (process " + std::to_string(rank) + " of " + std::to_string(size) + ")";
    while (true)
      {
        long taken = 0;
        MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window);
        MPI_Fetch_and_op(&one, &taken, MPI_LONG, 0, 0, MPI_SUM, window);
        MPI_Win_unlock(0, window);
        if (taken >= static_cast<long>(list.size())) break;
        const std::size_t i = list[taken];
        const auto start = std::chrono::steady_clock::now();
        const double cpu_start = process_cpu_seconds();
        std::string message;
        int code = 0;
        {
          std::error_code ec;
          fs::create_directories(cases[i].folder, ec);
          OutputToFile log(cases[i].folder + "/log.txt");
          code = run_case_here(study, cases[i], message);
        }
        finish_case(i, code, message, process_cpu_seconds() - cpu_start, seconds_since(start), who);
        if (code > 128) // interrupted: mpirun signalled the other processes too
          {
            stopped_by = code - 128;
            break;
          }
      }
    MPI_Barrier(MPI_COMM_WORLD);
    MPI_Win_free(&window);
    // The first process writes the table from every case's record.
    if (rank == 0) find_finished_cases();
    MPI_Allreduce(MPI_IN_PLACE, &stopped_by, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return stopped_by;
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
  double case_wall_time_sum() const
  {
    double sum = 0;
    for (std::size_t i = 0; i < cases.size(); ++i)
      if (done[i]) sum += records[i].wall_time_s;
    return sum;
  }

private:
  io::Study study;
  std::string folder;
  std::vector<io::StudyCase> cases;
  std::vector<CaseRecord> records;
  std::vector<bool> done;

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
    CaseRecord r;
    r.exit_status = code;
    r.status = status_of_exit(code);
    r.message = message;
    r.cpu_time_s = cpu;
    r.wall_time_s = wall;
    r.collected = io::collect_quantities(study.quantities, cases[i].folder);
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
        r.exit_status = tree.get<int>("exit_status");
        r.message = tree.get<std::string>("message");
        r.cpu_time_s = tree.get<double>("cpu_time_s");
        r.wall_time_s = tree.get<double>("wall_time_s");
        r.collected.clear();
        for (const auto &v : tree.get_child("collected")) r.collected.push_back(v.second.data());
        // A study whose quantities changed collects them again from the case's results.
        if (r.collected.size() != study.quantities.size()) r.collected = io::collect_quantities(study.quantities, c.folder);
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
  if (on_mpi && options.jobs > 1)
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
  Sweep sweep(options, file);
  const auto &study = sweep.the_study();
  if (rank == 0)
    std::cout << "flextrack sweep: " << options.file << "\n  scene " << study.scene << ", " << study.design << " design, "
              << sweep.size() << " cases, " << (on_mpi ? std::to_string(size) + " MPI processes" : std::to_string(options.jobs) + " at once (-j)")
              << "; results in " << sweep.output_folder() << "/" << std::endl;
  sweep.check_every_case();
  const unsigned int finished = sweep.find_finished_cases();
  const auto list = sweep.pending();
  if (rank == 0 && finished > 0)
    std::cout << "  " << finished << " cases finished by an earlier run of this study (case.json, same entries): " << list.size()
              << " to run" << std::endl;
  if (on_mpi) MPI_Barrier(MPI_COMM_WORLD); // every process has seen which cases are done
  const int signal = on_mpi ? sweep.run_on_mpi_process(list) : sweep.run_forked(list, options.jobs);
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
  if (!list.empty() && !on_mpi && options.jobs == 1)
    std::cout << ", of which " << std::max(0.0, wall - sweep.case_wall_time_sum()) << " s outside the cases (checks, fork, records, sweep.csv, plot)";
  std::cout << "\n  results in " << sweep.output_folder() << "/ (sweep.csv" << (plot.empty() ? "" : ", " + plot)
            << ", case_NNNN/)" << std::endl;
  if (n_done < sweep.size())
    throw base::Interrupted(signal ? signal : SIGTERM, "the study stopped with " + std::to_string(sweep.size() - n_done) +
                                      " cases to run; run it again to run only those");
  return 0;
}
} // namespace flextrack::app
