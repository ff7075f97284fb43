// flextrack: command-line entry point.
//
// Parses the command line, starts MPI where the command needs it (Trilinos' distributed
// matrices), runs one command, and turns every
// error a user can cause into one clear line on stderr and a non-zero exit status:
//   2 = bad input (file, entry, allowed values), 3 = solver failure, 4 = internal error.
#include <app/commands.h>
#include <app/exit_status.h>
#include <base/names.h>
#include <io/body_export.h>
#include <base/input_error.h>
#include <base/interrupt.h>
#include <base/mpi_session.h>


#include <mpi.h>

#include <dlfcn.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

namespace
{
const char *usage = R"(flextrack - flexible multibody systems on curved, flexible sliding tracks

Usage:
  flextrack                          run the default scene (the laser robot, prm/laser_robot.prm)
  flextrack run FILE.prm [-o DIR]    simulate a multibody scene ('Model = multibody',
                                     doc/multibody.md); other scenes: as 'modes'
  flextrack sweep STUDY.prm [-j N] [-o DIR]
                                     a parameter study ('Model = study', doc/sweep.md): the
                                     study's scene run for every case, N cases at once (default:
                                     one per core this process may use), into
                                     DIR/case_NNNN/; one row per case in DIR/sweep.csv, and
                                     sweep.png; run again, it runs only the unfinished cases
  mpirun -np N flextrack sweep ...   the same, the cases shared out over the N processes
  flextrack linearize FILE.prm       frequencies and damping ratios of a multibody scene
                                     linearised about its initial state
  flextrack bench FILE.prm [-o DIR]  work-precision of the integrators on a multibody scene: a
                                     reference run, IDA at rtol 1e-3 ... 1e-10, generalised-alpha
                                     at 8 step sizes; error at the probes against wall time
  flextrack modes FILE.prm [-o DIR]  natural frequencies and mode shapes of the arm or solid in FILE
  mpirun -np N flextrack modes ...   the same for a solid, its mesh partitioned over N processes
  flextrack converge FILE.prm --refinements K [-o DIR]
                                     the same on K successively halved meshes, with the change
                                     and observed order of convergence of every frequency
  flextrack reduce FILE.prm [-o DIR] reduce the flexible body of a 'Model = body' scene to
                                     DIR/reduced_body.h5 (reused while its inputs are unchanged)
  mpirun -np N flextrack reduce ...  the same, factorised (MUMPS) and solved (PARPACK) on N
                                     processes, for bodies whose factor outgrows one process
  flextrack static FILE.prm [-o DIR] linear static solution of an arm or solid under the scene's
                                     load cases: displacements, reactions, strain energy
  flextrack inspect BODY.h5          print what a reduced body file holds
  flextrack export --format FORMAT BODY.h5 [-o DIR] [--mbdyn-clamp auto|yes|no]
                                     the reduced body for other tools: 'mbdyn' (BODY.fem modal
                                     element data + BODY.elm joint statement), 'vtu' (mode
                                     shapes, BODY_modes.vtu, for ParaView / meshio);
                                     --mbdyn-clamp: clamp the modal node (auto: if the body has
                                     supports; no: for a body on a joint, doc/exports.md)
  flextrack print-parameters         every parameter: default, allowed values, unit, meaning
  flextrack --help | --version

Every command that reads a scene FILE also takes, repeatable:
  --set ENTRY=VALUE                  set an entry after the file (checked like the file's own),
                                     ENTRY as print-parameters shows it, e.g.
                                     --set "Multibody/End time=5"; "Body NAME:ENTRY" sets an
                                     entry of flexible body NAME's body scene

Results go to DIR (default: output/<FILE name without extension>/):
  frequencies.csv   mode, frequency [Hz]
  summary.json      degrees of freedom, frequencies, wall time per stage, parameters used
  mode_shapes.pvd   mass-normalised mode shapes (VTU series; open in ParaView)
  convergence.csv, convergence.png   (converge)
  probes.csv, monitors.csv, results.h5   (run: probe positions and velocities, constraint
                    residuals and energy balance, the full state; written up to a solver failure)
  sweep.csv, sweep.png   (sweep: parameters, collected quantities, status, CPU time per case)
  bench.csv, bench.png   (bench: method, setting, error per probe, wall time, steps, evaluations)
  static.csv        load case, arc length, position, displacement, rotation (static)
  reduced_body.h5   reduced matrices, inertia invariants, interface and arm mode fields (reduce;
                    layout in doc/reduced_body_file.md)
Exit status: 0 success, 1 usage error, 2 bad input, 3 solver failure, 4 internal error.
)";

std::string default_scene()
{
  // From the repository root, or wherever the program was built from.
  for (const std::string candidate : {"prm/laser_robot.prm", FLEXTRACK_SOURCE_DIR "/prm/laser_robot.prm"})
    if (std::filesystem::exists(candidate)) return candidate;
  return "prm/laser_robot.prm";
}

int usage_error(const std::string &message)
{
  std::cerr << "flextrack: " << message << "\n(see flextrack --help)" << std::endl;
  return 1;
}

/// This process's own folder for Open MPI's session files (base::prepare_singleton_mpi), removed
/// at exit.
std::string private_mpi_folder;

/// MPI is started only by the commands that use Trilinos' distributed matrices (every other
/// command starts faster without it, and cannot fail in OpenMPI's singleton start-up).
void start_mpi(int *argc, char ***argv)
{
  int started = 0;
  MPI_Initialized(&started);
  if (started) return;
  private_mpi_folder = flextrack::base::prepare_singleton_mpi();
  MPI_Init(argc, argv);
  // Under mpirun every process computes; only the first one talks (errors excepted).
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) std::cout.rdbuf(nullptr);
}

using namespace flextrack::app;

/// The commands, one row each: name, whether it needs MPI, whether it reads a scene, and the
/// function (scene commands get the scene file read once; the others get the options only).
struct Command
{
  const char *name;
  bool needs_mpi;
  int (*on_scene)(const Options &, const flextrack::io::SceneFile &);
  int (*on_options)(const Options &);
};

int scene_dispatch(const Options &options, const flextrack::io::SceneFile &file)
{
  // 'modes' on a body scene reduces the body: the scene decides, read once.
  if (file.model == "body") return reduce_command(options, file);
  return modes_command(options, file);
}

/// 'run' simulates a multibody scene; other scenes keep their analysis ('modes' or 'reduce').
int run_dispatch(const Options &options, const flextrack::io::SceneFile &file)
{
  if (file.model == "multibody")
    {
      if (flextrack::base::started_by_mpirun())
        {
          // Said once, by the first process (MPI is not started here: the launcher's rank).
          const char *rank = std::getenv("OMPI_COMM_WORLD_RANK");
          if (!rank) rank = std::getenv("PMIX_RANK");
          if (rank && std::atoi(rank) != 0) return 2;
          throw flextrack::InputError("", "'flextrack run' of a multibody scene runs on one process: start it without "
                                          "mpirun (studies: mpirun ... flextrack sweep; large bodies: mpirun ... flextrack "
                                          "reduce BODY.prm first)",
                                      options.file);
        }
      return run_command(options, file);
    }
  if (file.model == "study")
    throw flextrack::InputError("Model", "is 'study': run a study with 'flextrack sweep " + options.file + "'", options.file);
  start_mpi(nullptr, nullptr);
  return scene_dispatch(options, file);
}

const std::vector<Command> &commands()
{
  // run and linearize start MPI only when they reduce a body (start_mpi_for_reduction).
  static const std::vector<Command> table{{"run", false, run_dispatch, nullptr},
                                          {"linearize", false, linearize_command, nullptr},
                                          {"bench", false, bench_command, nullptr},
                                          {"sweep", false, sweep_command, nullptr},
                                          {"modes", true, scene_dispatch, nullptr},
                                          {"converge", true, converge_command, nullptr},
                                          {"reduce", true, reduce_command, nullptr},
                                          {"static", true, static_command, nullptr},
                                          {"inspect", false, nullptr, inspect_command},
                                          {"export", false, nullptr, export_command}};
  return table;
}

/// True, with @p value set, if @p text is a whole integer from @p lowest to @p highest.
bool integer_in(const std::string &text, const int lowest, const int highest, unsigned int &value)
{
  try
    {
      std::size_t used = 0;
      const int n = std::stoi(text, &used);
      if (used != text.size() || n < lowest || n > highest) return false;
      value = n;
      return true;
    }
  catch (...)
    {
      return false;
    }
}

/// Options after the command name; returns a usage message, empty if they are fine.
std::string parse_options(const std::string &command, const std::vector<std::string> &args, Options &options)
{
  bool have_refinements = false;
  for (std::size_t i = 1; i < args.size(); ++i)
    {
      if (args[i] == "-o" || args[i] == "--output")
        {
          if (++i == args.size()) return "-o needs a folder name";
          options.output_directory = args[i];
        }
      else if (args[i] == "--refinements" && command == "converge")
        {
          if (++i == args.size()) return "--refinements needs a number";
          if (!integer_in(args[i], 1, 12, options.refinements))
            return "--refinements must be an integer from 1 to 12, not '" + flextrack::base::printable_excerpt(args[i]) + "'";
          have_refinements = true;
        }
      else if ((args[i] == "-j" || args[i] == "--jobs") && command == "sweep")
        {
          if (++i == args.size()) return "-j needs the number of cases to run at once";
          // At most 256 workers: two pipes each stay well inside the usual limit of 1024 open files.
          if (!integer_in(args[i], 1, 256, options.jobs))
            return "-j must be an integer from 1 to 256, not '" + flextrack::base::printable_excerpt(args[i]) + "'";
        }
      else if (args[i] == "--format" && command == "export")
        {
          if (++i == args.size()) return "--format needs a format name: " + flextrack::io::export_format_list();
          options.format = args[i];
        }
      else if (args[i] == "--mbdyn-clamp" && command == "export")
        {
          if (++i == args.size()) return "--mbdyn-clamp needs a value: auto, yes or no";
          options.mbdyn_clamp = args[i]; // checked by export_command (bad input, exit 2)
        }
      else if (args[i] == "--set")
        {
          if (++i == args.size()) return "--set needs ENTRY=VALUE, e.g. --set \"Multibody/End time=5\"";
          options.overrides.push_back(flextrack::io::parse_override(args[i])); // InputError: exit 2
        }
      else if (args[i].rfind("--set=", 0) == 0)
        options.overrides.push_back(flextrack::io::parse_override(args[i].substr(6)));
      else if (!args[i].empty() && args[i][0] == '-')
        return "unknown option '" + flextrack::base::printable_excerpt(args[i]) + "' for " + command;
      else if (options.file.empty())
        options.file = args[i];
      else
        return "more than one input file given ('" + options.file + "', '" + args[i] + "')";
    }
  if (options.file.empty())
    return command + (command == "inspect" || command == "export" ? " needs a reduced body file" : " needs a parameter file");
  if (command == "converge" && !have_refinements) return "converge needs --refinements K";
  if (command == "export" && options.format.empty())
    return "export needs --format FORMAT; allowed: " + flextrack::io::export_format_list();
  return "";
}

int dispatch(std::vector<std::string> args, int *argc, char ***argv)
{
  if (args.empty()) args = {"run", default_scene()};
  const std::string &command = args[0];
  if (command == "--help" || command == "-h" || command == "help")
    {
      std::cout << usage;
      return 0;
    }
  if (command == "--version")
    {
      std::cout << "flextrack " FLEXTRACK_VERSION << std::endl;
      return 0;
    }
  if (command == "print-parameters")
    {
      const int status = print_parameters_command();
      print_multibody_parameters();
      return status;
    }
  const auto &table = commands();
  const auto row = std::find_if(table.begin(), table.end(), [&](const Command &c) { return command == c.name; });
  if (row == table.end())
    return usage_error("unknown command '" + flextrack::base::printable_excerpt(command) +
                       "'; allowed: run, linearize, bench, sweep, modes, converge, reduce, static, inspect, export, print-parameters");
  Options options;
  if (const auto problem = parse_options(command, args, options); !problem.empty()) return usage_error(problem);
  // A multibody simulation runs on one process; under mpirun every process would run it and
  // write the same files (and reduce its bodies together while holding their cache locks).
  if (flextrack::base::started_by_mpirun() && (command == "linearize" || command == "bench"))
    return usage_error("'" + command + "' runs on one process: start it without mpirun (mpirun -np N flextrack sweep "
                       "shares the cases of a study over N processes)");
  if (row->needs_mpi)
    {
      start_mpi(argc, argv);
      start_collective_work(); // these commands work on distributed matrices under mpirun
    }
  if (row->on_options) return row->on_options(options);
  return row->on_scene(options, flextrack::io::SceneFile::read(options.file, options.overrides));
}
} // namespace

void flextrack::app::start_mpi_for_reduction() { start_mpi(nullptr, nullptr); }

namespace
{
/// Debian's OpenBLAS (pthreads) starts one worker per core, and after a threaded call they spin in
/// sched_yield: on the laser robot and the slewing beam they took 10-15 % of the CPU samples (perf)
/// from the other core, for BLAS calls on matrices of tens of rows. FlexTrack's dense algebra is
/// small, so one thread. Looked up at run time: another BLAS (the reference one, BLIS) may be
/// installed as the alternative, and then there is nothing to do.
void use_one_blas_thread()
{
  using SetThreads = void (*)(int);
  if (const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
  // The worker OpenBLAS started when it was loaded spins in sched_yield until its timeout (2^28
  // cycles, about 0.1 s) before it sleeps: 0.05 s of CPU on the other core in every run (perf on
  // the laser robot). With one thread it is never needed; OpenBLAS starts it again if a later
  // call asks for more threads.
  using Shutdown = int (*)();
  if (const auto stop = reinterpret_cast<Shutdown>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_"))) stop();
}
} // namespace

int main(int argc, char **argv)
{
  // The log line by line also when stdout is a file or a pipe (batch runs, sweeps): block
  // buffering held every progress line back to the end, and a killed run lost them (issue 25,
  // item 8). std::cout writes through C's stdout (synchronised, the default).
  std::setvbuf(stdout, nullptr, _IOLBF, BUFSIZ);
  use_one_blas_thread();
  const auto outcome = run_guarded([&] { return dispatch(std::vector<std::string>(argv + 1, argv + argc), &argc, &argv); });
  if (!outcome.message.empty()) std::cerr << "flextrack: " << outcome.message << std::endl;
  const int status = outcome.status;
  int started = 0, finished = 0;
  MPI_Initialized(&started);
  MPI_Finalized(&finished);
  if (started && !finished && status != 0 && collective_work_started())
    {
      // A failure on some processes of a collective command (a distributed reduction whose
      // first process cannot write its file) would leave the others waiting in a collective
      // step, and MPI_Finalize waits for them: end every process with this status instead.
      int size = 1;
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      if (size > 1) MPI_Abort(MPI_COMM_WORLD, status);
    }
  if (started && !finished) MPI_Finalize();
  flextrack::base::remove_mpi_session_folder(private_mpi_folder);
  return status;
}
