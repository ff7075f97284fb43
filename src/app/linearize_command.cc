// flextrack linearize: the eigenvalues of a multibody scene linearised about its initial state
// (made consistent first; multibody/linearization.h): frequencies and damping ratios on stdout.
// A static equilibrium or a steady motion (a hub spinning at a constant driven rate) is the
// state to give; nothing is integrated. Written to the output folder (-o, Output/Directory or
// output/<scene>): linear_modes.csv (mode, frequency, damping ratio, eigenvalue) and summary.json.
#include <app/commands.h>
#include <base/input_error.h>
#include <io/multibody_scene.h>
#include <io/output_folder.h>
#include <multibody/initial_conditions.h>
#include <multibody/linearization.h>

#include <deal.II/base/timer.h>

#include <iomanip>
#include <iostream>
#include <sstream>

namespace flextrack::app
{
using namespace dealii;

int linearize_command(const Options &options, const io::SceneFile &file)
{
  CommandClock clock;
  auto &timer = clock.timer;
  std::cout << "flextrack linearize: " << options.file << std::endl;
  io::MultibodyScene scene;
  {
    TimerOutput::Scope t(timer, "read scene, build bodies");
    scene = io::read_multibody_scene(file, std::cout, timer, start_mpi_for_reduction);
  }
  auto &system = *scene.system;
  const double t0 = scene.settings.start_time;
  Vector<double> y, yp;
  std::vector<multibody::LinearMode> modes;
  {
    TimerOutput::Scope t(timer, "initial conditions");
    try
      {
        multibody::InitialConditionSettings initial; // Multibody/Initial state: linearise about the equilibrium
        initial.static_equilibrium = scene.settings.static_equilibrium;
        const std::string report = multibody::consistent_initial_conditions(system, t0, y, yp, initial).text();
        std::cout << "  " << report; // after the call: a refused start leaves no stray indent
      }
    catch (const InputError &e)
      {
        throw e.file().empty() ? e.in_file(scene.file) : e;
      }
  }
  {
    TimerOutput::Scope t(timer, "linearise, eigenvalues");
    modes = multibody::linearize(system, t0, y);
  }
  std::cout << "\n  linearised at t = " << t0 << " s: " << modes.size() << " modes\n"
            << "  mode   frequency [Hz]    damping ratio [-]   eigenvalue [1/s]\n";
  // A zero eigenvalue (a neutral motion: a slider free along a level track) comes out of the
  // eigen solver as round-off of the size of the largest |s| times about 1e-11; judged against its
  // own |s| it was called UNSTABLE (Re s = 4e-6 among modes up to 1e5 1/s, issue 25, item 4).
  double largest = 1.0;
  for (const auto &m : modes) largest = std::max(largest, std::abs(m.eigenvalue));
  const double round_off = 1e-10 * largest;
  unsigned int unstable = 0;
  for (unsigned int k = 0; k < modes.size(); ++k)
    {
      const auto &m = modes[k];
      const bool grows = m.eigenvalue.real() > std::max(round_off, 1e-9 * std::abs(m.eigenvalue));
      unstable += grows;
      std::cout << "  " << std::setw(4) << k + 1 << "  " << std::setw(16) << std::setprecision(10) << m.frequency_hz
                << "  " << std::setw(17) << std::setprecision(6) << m.damping_ratio << "   " << std::setprecision(6)
                << m.eigenvalue.real() << (m.eigenvalue.imag() < 0 ? " - " : " + ") << std::abs(m.eigenvalue.imag())
                << " i" << (grows ? "   UNSTABLE" : "") << "\n";
    }
  if (unstable) std::cout << "  " << unstable << " mode(s) with Re s > 0: the state is unstable\n";

  io::OutputFolder out(io::OutputFolder::choose(options.output_directory, scene.output_directory, options.file));
  out.tidy_previous_run("linearize");
  std::ostringstream csv;
  csv << "mode,frequency_Hz,damping_ratio,eigenvalue_real_per_s,eigenvalue_imag_per_s\n";
  for (unsigned int k = 0; k < modes.size(); ++k)
    csv << k + 1 << "," << io::csv_number(modes[k].frequency_hz) << "," << io::csv_number(modes[k].damping_ratio) << ","
        << io::csv_number(modes[k].eigenvalue.real()) << "," << io::csv_number(modes[k].eigenvalue.imag()) << "\n";
  out.add_text("linear_modes.csv", csv.str());
  io::JsonObject summary;
  std::vector<double> frequencies;
  for (const auto &m : modes) frequencies.push_back(m.frequency_hz);
  summary.add("program", "flextrack " FLEXTRACK_VERSION)
    .add("command", "linearize")
    .add("parameter_file", options.file)
      .add("set_on_command_line", io::override_texts(options.overrides))
    .add("time_s", t0)
    .add("modes", static_cast<unsigned int>(modes.size()))
    .add("frequencies_Hz", frequencies)
    .add("unstable_modes", unstable)
    .add("total_wall_time_s", clock.total_for_summary())
    .raw("parameters", io::parameters_as_json(*scene.parameters));
  out.add_summary(summary);
  out.commit();
  std::cout << "  results in " << out.path() << "/ (linear_modes.csv, summary.json)\n";
  print_timings(clock);
  return 0;
}
} // namespace flextrack::app
