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
  // One verdict for this table and for the static equilibrium of 'run' (multibody/linearization.h:
  // round-off on a zero eigenvalue is not called UNSTABLE).
  const multibody::StabilityVerdict verdict = multibody::classify_stability(modes);
  for (unsigned int k = 0; k < modes.size(); ++k)
    {
      const auto &m = modes[k];
      std::cout << "  " << std::setw(4) << k + 1 << "  " << std::setw(16) << std::setprecision(10) << m.frequency_hz
                << "  " << std::setw(17) << std::setprecision(6) << m.damping_ratio << "   " << std::setprecision(6)
                << m.eigenvalue.real() << (m.eigenvalue.imag() < 0 ? " - " : " + ") << std::abs(m.eigenvalue.imag())
                << " i" << (verdict.grows[k] ? "   UNSTABLE" : "") << "\n";
    }
  if (verdict.unstable_modes)
    std::cout << "  " << verdict.unstable_modes << " mode(s) with Re s > 0: the state is unstable (fastest growth "
              << std::setprecision(9) << verdict.largest_growth_rate << " 1/s)\n";
  // Linearising about a state that is not an equilibrium (v' != 0) is allowed but said (issue 25,
  // item 4): a steady motion has v' = 0 too, a pendulum held at 30 degrees does not.
  std::vector<std::string> notes = scene.notes;
  const multibody::EquilibriumCheck balance = multibody::check_equilibrium(system, t0, y, yp);
  if (!balance.is_equilibrium()) notes.push_back(balance.note());
  for (const auto &n : notes) std::cout << "  note: " << n << "\n";

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
    .add("unstable_modes", verdict.unstable_modes)
    .add("largest_growth_rate_per_s", verdict.largest_growth_rate);
  io::JsonObject state;
  state.add("imbalance", balance.imbalance).add("tolerance", multibody::EquilibriumCheck::tolerance)
    .raw("is_equilibrium", balance.is_equilibrium() ? "true" : "false");
  if (!balance.name.empty())
    state.add("largest_acceleration_component", balance.name).add("largest_acceleration", balance.acceleration)
      .add("largest_acceleration_unit", balance.unit);
  summary.add("equilibrium_check", state)
    .add("notes", notes)
    .add("total_wall_time_s", clock.total_for_summary())
    .raw("parameters", io::parameters_as_json(*scene.parameters));
  out.add_summary(summary);
  out.commit();
  std::cout << "  results in " << out.path() << "/ (linear_modes.csv, summary.json)\n";
  print_timings(clock);
  return 0;
}
} // namespace flextrack::app
