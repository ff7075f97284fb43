// flextrack reduce: the reduced body of a flexible body scene (io/reduced_body_cache.h: loaded
// when up to date, else built and written), its text results and exports.
// flextrack inspect: print what a reduced body file holds.
#include <app/commands.h>
#include <app/exit_status.h>
#include <base/input_error.h>
#include <base/mpi_session.h>
#include <io/body_export.h>
#include <io/body_scene.h>
#include <io/output_folder.h>
#include <io/reduced_body_cache.h>
#include <io/reduced_body_file.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <iomanip>
#include <iostream>
#include <sstream>

namespace flextrack::app
{
using namespace dealii;

namespace
{
void print_reduced_body(const reduction::ReducedBody &b)
{
  const auto &inv = b.invariants;
  const auto c = inv.centre_of_mass();
  const auto J = inv.inertia_about_centre_of_mass();
  std::cout << "  method: " << b.method << "; " << b.n_modes() << " modes (" << b.n_normal << " normal, "
            << b.n_interface << " interface, " << b.n_track << " track load) from " << b.n_body_dofs
            << " body dofs (" << b.n_full_dofs << " before ties and supports)\n"
            << std::setprecision(8) << "  mass " << inv.mass << " kg; centre of mass (" << c[0] << ", " << c[1] << ", "
            << c[2] << ") m\n  inertia about the centre of mass [kg m^2]: (" << J[0][0] << ", " << J[1][1] << ", "
            << J[2][2] << "; " << J[0][1] << ", " << J[0][2] << ", " << J[1][2] << ")\n  interfaces:";
  for (const auto &p : b.interfaces)
    std::cout << " " << p.name << " (" << p.position[0] << ", " << p.position[1] << ", " << p.position[2] << ")";
  if (b.interfaces.empty()) std::cout << " none";
  std::cout << "\n  arms:";
  for (const auto &a : b.arms) std::cout << " " << a.name << " (L = " << a.length() << " m, " << a.n_cells() << " cells)";
  if (b.arms.empty()) std::cout << " none";
  std::cout << "\n\n  mode  frequency [Hz]\n";
  for (unsigned int k = 0; k < b.frequencies_hz.size(); ++k)
    std::cout << "  " << std::setw(4) << k + 1 << "  " << std::setprecision(10) << b.frequencies_hz[k] << "\n";
}
} // namespace

int reduce_command(const Options &options, const io::SceneFile &file)
{
  // Under mpirun the reduction is distributed (assembly, factorisation, eigen solve); the first
  // process writes the body and the results, the others only take part.
  const unsigned int n_processes = base::fe_processes();
  CommandClock clock;
  auto &timer = clock.timer;
  io::BodyScene scene;
  {
    TimerOutput::Scope t(timer, "read parameters and geometry");
    scene = io::read_body_scene(file);
  }
  io::OutputFolder out(io::OutputFolder::choose(options.output_directory, scene.output.directory, options.file));
  const std::string body_file = out.path() + "/reduced_body.h5";
  std::cout << "flextrack reduce: " << options.file << " (input hash " << scene.input_hash << ")" << std::endl;
  if (n_processes > 1)
    {
      start_collective_work(); // also when 'run' of a body scene got here
      std::cout << "  distributed over " << n_processes << " processes (MPI): the solid partitioned by METIS, each "
                << "process assembles and holds its own rows of K and M; MUMPS factorises, PARPACK solves the "
                << "eigenproblem" << std::endl;
    }
  const auto obtained = io::cached_or_reduced_body(scene, body_file, std::cout, timer);
  const auto &body = obtained.body;
  // Each process' peak so far (the reduction's), for the memory a distributed run needs.
  std::vector<double> peaks{io::peak_memory_mib()};
  if (n_processes > 1) peaks = Utilities::MPI::all_gather(base::fe_communicator(), peaks[0]);
  if (!io::is_first_process()) return 0;

  // Text results and exports (also after a cache hit: they describe this run).
  std::vector<std::string> exported;
  for (const auto &format : scene.output.export_formats)
    for (const auto &f : io::export_reduced_body(body, io::find_export_format(format, "Output/Export formats"), out,
                                                 "reduced_body"))
      exported.push_back(f);
  out.add_frequencies(body.frequencies_hz);
  out.add_parameters(*scene.parameters);
  io::JsonObject summary;
  summary.add("program", "flextrack " FLEXTRACK_VERSION)
    .add("command", "reduce")
    .add("parameter_file", options.file)
      .add("set_on_command_line", io::override_texts(options.overrides))
    .add("reduced_body_file", body_file)
    .add("input_hash", scene.input_hash)
    .raw("loaded_from_cache", obtained.from_cache ? "true" : "false")
    .add("method", body.method)
    .add("mpi_processes", n_processes)
    .add("body_degrees_of_freedom", body.n_body_dofs)
    .add("modes", body.n_modes())
    .add("frequencies_Hz", body.frequencies_hz)
    .add("mass_kg", body.invariants.mass)
    .raw("check_against_full_model", obtained.checked ? obtained.check.str(4) : "null")
    .add("wall_time_s", io::timings_json(timer))
    .add("total_wall_time_s", clock.total_for_summary())
    .add("peak_memory_MiB", io::peak_memory_mib())
    .add("peak_memory_per_process_MiB", peaks)
    .raw("parameters", io::parameters_as_json(*scene.parameters));
  out.add_summary(summary);
  out.commit();

  print_reduced_body(body);
  std::cout << "\n";
  print_timings(clock);
  if (n_processes > 1)
    {
      double sum = 0;
      std::cout << "  peak memory per process [MiB]:";
      for (const double p : peaks)
        {
          std::cout << " " << std::setprecision(4) << p;
          sum += p;
        }
      std::cout << "; " << sum << " in all\n";
    }
  std::cout << "  results in " << out.path() << "/ (reduced_body.h5, frequencies.csv, summary.json";
  for (const auto &f : exported) std::cout << ", " << f;
  std::cout << ")" << std::endl;
  return 0;
}

int inspect_command(const Options &options)
{
  const auto body = io::read_reduced_body(options.file);
  std::cout << "flextrack inspect: " << options.file << "\n  written from " << body.source << " (input hash "
            << body.input_hash << ")\n";
  print_reduced_body(body);
  return 0;
}

void print_timings(const CommandClock &clock)
{
  std::cout << "  wall time [s]:";
  for (const auto &[name, seconds] : clock.timer.get_summary_data(TimerOutput::total_wall_time))
    std::cout << "  " << name << " " << std::setprecision(3) << seconds << ";";
  if (clock.summary_total >= 0)
    std::cout << "  total " << clock.summary_total << " (summary.json; stages may nest), then "
              << clock.wall.wall_time() - clock.summary_total << " s to commit the files and draw the plots";
  else
    std::cout << "  total " << clock.wall.wall_time() << " (stages may nest)";
  std::cout << "\n  peak memory: " << std::setprecision(4) << io::peak_memory_mib() << " MiB\n";
}
} // namespace flextrack::app
