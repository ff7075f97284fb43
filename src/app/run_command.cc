// flextrack run: the time simulation of a multibody scene, step-44 style: read the scene and
// build the system (io), make the initial conditions consistent, integrate (multibody: IDA or generalised-alpha),
// record probes, monitors and the state at every output time (io), summarise.
//
// The output rule of every command holds for bad input: nothing is written. A solver failure is
// different: the rows recorded up to the failure are results the user needs to see what went
// wrong, so they are committed (with summary.json saying "failed" and where), and the failure is
// then reported with exit status 3.
#include <app/commands.h>
#include <app/multibody_runs.h>
#include <base/input_error.h>
#include <base/interrupt.h>
#include <base/solver_error.h>
#include <base/text.h>
#include <io/animation_writer.h>
#include <io/gnuplot.h>
#include <io/multibody_scene.h>
#include <io/output_folder.h>
#include <io/path_deviation.h>
#include <io/run_results.h>
#include <multibody/initial_conditions.h>
#include <multibody/monitors.h>

#include <unistd.h>

#include <deal.II/base/timer.h>

#include <algorithm>
#include <functional>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

namespace flextrack::app
{
using namespace dealii;
using multibody::MonitorValues;

namespace
{
/// Progress of the integration: a line rewritten in place on a terminal, else a plain log line
/// every tenth of the simulated time.
class ProgressReport
{
public:
  ProgressReport(const double t0, const double t_end) : t0(t0), t_end(t_end), terminal(isatty(STDOUT_FILENO)) {}
  void update(const double t, const long steps)
  {
    const double fraction = (t - t0) / (t_end - t0);
    const double seconds = clock.wall_time();
    if (terminal && seconds - last_print < 0.2 && t < t_end) return;
    if (!terminal && fraction < next_fraction - 1e-12) return;
    std::ostringstream line;
    line << "  t = " << std::setprecision(6) << t << " s (" << std::setprecision(3) << 100 * fraction << " %), "
         << steps << " steps, " << std::setprecision(3) << (seconds > 0 ? (t - t0) / seconds : 0.0)
         << " s simulated per s";
    if (terminal)
      std::cout << "\r" << std::left << std::setw(78) << line.str() << std::flush;
    else
      std::cout << line.str() << "\n";
    last_print = seconds;
    while (next_fraction <= fraction + 1e-12) next_fraction += 0.1;
  }
  void finish() const
  {
    if (terminal) std::cout << "\n";
  }

private:
  double t0, t_end;
  bool terminal;
  Timer clock;
  double last_print = -1, next_fraction = 0;
};

/// The unknowns that most often had the largest weighted local error of a step (IDA), most
/// frequent first, at most @p count of them: what limits the step size.
std::vector<std::pair<std::string, long>> step_limiters(const multibody::IntegratorStatistics &s,
                                                        const multibody::System &system, const unsigned int count)
{
  std::vector<unsigned int> order(s.steps_limited_by.size());
  for (unsigned int i = 0; i < order.size(); ++i) order[i] = i;
  const unsigned int k = std::min<unsigned int>(count, order.size());
  std::partial_sort(order.begin(), order.begin() + k, order.end(),
                    [&](const unsigned int a, const unsigned int b) { return s.steps_limited_by[a] > s.steps_limited_by[b]; });
  std::vector<std::pair<std::string, long>> top;
  for (unsigned int i = 0; i < k && s.steps_limited_by[order[i]] > 0; ++i)
    top.emplace_back(system.component_name(order[i]), s.steps_limited_by[order[i]]);
  return top;
}

void print_step_limiters(const multibody::IntegratorStatistics &s, const multibody::System &system)
{
  const auto top = step_limiters(s, system, 3);
  if (top.empty()) return;
  std::cout << "  steps limited by (largest weighted local error):";
  for (const auto &[name, steps] : top)
    std::cout << " " << name << " " << std::setprecision(2) << 100.0 * steps / std::max(1L, s.steps) << " %;";
  std::cout << "\n";
}

io::JsonObject statistics_json(const multibody::IntegratorStatistics &s, const multibody::System &system)
{
  io::JsonObject j;
  std::vector<double> histogram(s.order_histogram.begin() + 1, s.order_histogram.end());
  j.add("steps", static_cast<double>(s.steps))
    .add("rejected_steps_error_test", static_cast<double>(s.error_test_failures))
    .add("rejected_steps_nonlinear_convergence", static_cast<double>(s.nonlinear_convergence_failures))
    .add("newton_restarts_with_new_jacobian", static_cast<double>(s.newton_restarts))
    .add("order_histogram_1_to_5", histogram)
    .add("nonlinear_iterations", static_cast<double>(s.nonlinear_iterations))
    .add("residual_evaluations", static_cast<double>(s.residual_evaluations))
    .add("jacobian_evaluations", static_cast<double>(s.jacobian_evaluations))
    .add("factorizations", static_cast<double>(s.factorizations))
    .add("factorizations_with_positions_condensed", static_cast<double>(s.condensed_factorizations))
    .add("last_step_s", s.last_step);
  io::JsonObject limiters; // unknown -> steps at which it had the largest weighted local error
  for (const auto &[name, steps] : step_limiters(s, system, 5)) limiters.add(name, static_cast<double>(steps));
  j.add("steps_limited_by", limiters);
  return j;
}

io::JsonObject initial_conditions_json(const multibody::InitialConditionReport &r)
{
  io::JsonObject j;
  j.add("iterations", r.iterations).add("position_residual", r.position_residual).add("velocity_residual", r.velocity_residual);
  std::string corrections = "[", dropped = "[";
  for (const auto &c : r.corrections)
    {
      io::JsonObject b;
      b.add("body", c.body).add("moved_m", c.displacement).add("turned_rad", c.rotation).add("modal_change", c.modal).add("velocity_change", c.velocity);
      corrections += (corrections.size() > 1 ? ", " : "") + b.str(4);
    }
  for (const auto &d : r.dropped)
    dropped += (dropped.size() > 1 ? ", " : "") +
               io::JsonObject::quote("joint " + d.joint + ", equation " + std::to_string(d.equation) + " (" + d.description + ")");
  j.raw("corrections", corrections + "]").raw("dropped_redundant_equations", dropped + "]");
  if (r.equilibrium.solved)
    {
      const auto &e = r.equilibrium;
      io::JsonObject eq;
      std::string moves = "[";
      for (const auto &m : e.moves)
        {
          io::JsonObject b;
          b.add("body", m.body).add("moved_m", m.displacement).add("turned_rad", m.rotation).add("modal_change", m.modal);
          moves += (moves.size() > 1 ? ", " : "") + b.str(6);
        }
      eq.add("iterations", e.iterations)
        .add("force_residual", e.force_residual)
        .add("largest_load", e.load_scale)
        .add("position_residual", e.position_residual)
        .raw("stable", e.stable ? "true" : "false")
        .add("unstable_modes", e.unstable_modes)
        .add("growth_rate_per_s", e.growth_rate)
        .raw("moves", moves + "]");
      j.raw("static_equilibrium", eq.str(4));
    }
  return j;
}
/// Multibody/Rigid reference: the scene of @p file run again with every body rigid, and the
/// deviation of @p run's probe paths from its paths. A failure of that run (bad initial
/// conditions, solver, end of track) goes to @p failure: the deviation then covers the rows it
/// reached, and the main run's results are kept.
io::PathDeviation rigid_reference_deviation(const io::SceneFile &file, const io::ProbePaths &run, TimerOutput &timer,
                                            std::string &failure)
{
  std::ostringstream log; // the bodies were reported by the main run
  io::MultibodyScene rigid = io::read_multibody_scene(file, log, timer, start_mpi_for_reduction, true);
  io::ProbePaths paths(*rigid.system, rigid.probes);
  try
    {
      Vector<double> y, yp;
      consistent_start(rigid, y, yp);
      const auto owned_integrator = multibody::make_integrator(*rigid.system, rigid.settings.integrator);
      auto &integrator = *owned_integrator;
      integrator.initialize(rigid.settings.start_time, y, yp);
      paths.record(rigid.settings.start_time, y);
      failure = integrate(*rigid.system, integrator, rigid.settings,
                          [&](const double time, const Vector<double> &state) { paths.record(time, state); });
    }
  catch (const InputError &e)
    {
      failure = e.what();
    }
  catch (const SolverError &e)
    {
      failure = e.what();
    }
  return io::PathDeviation(run, paths);
}
} // namespace

void print_multibody_parameters()
{
  ParameterHandler prm;
  multibody::SceneNames names;
  names.bodies = names.joints = names.forces = names.probes = {"NAME"};
  io::declare_multibody_scene(prm, names);
  std::cout << "\n# Model = multibody (flextrack run, flextrack linearize; doc/multibody.md): one body,\n"
               "# joint, force and probe called NAME\n";
  prm.print_parameters(std::cout, ParameterHandler::PRM);
}

int run_command(const Options &options, const io::SceneFile &file)
{
  CommandClock clock;
  auto &timer = clock.timer;
  std::cout << "flextrack run: " << options.file << std::endl;
  io::MultibodyScene scene;
  {
    TimerOutput::Scope t(timer, "read scene, build bodies");
    scene = io::read_multibody_scene(file, std::cout, timer, start_mpi_for_reduction);
  }
  auto &system = *scene.system;
  const auto &settings = scene.settings;
  for (const auto &d : scene.body_descriptions) std::cout << "  body " << d << "\n";
  for (const auto &n : scene.notes) std::cout << "  note: " << n << "\n";
  std::cout << "  " << system.n_joints() << " joints, " << system.n_forces() << " forces, " << scene.probes.size()
            << " probes; " << system.size() << " unknowns (" << system.n_q() << " positions, " << system.n_v()
            << " velocities, " << system.n_lambda() + system.n_mu() << " multipliers)" << std::endl;

  // Output volume before the run (issue 23): 1e7 rows wrote 161 MB of CSV a minute and a 1.9 GB
  // results.h5 (now written in blocks as the run goes, no longer held in memory).
  const double rows = settings.output_interval > 0 ? (settings.end_time - settings.start_time) / settings.output_interval + 2 : 2;
  const double gib = rows * io::RunRecorder::bytes_per_row(system, scene.probes.size()) / (1024.0 * 1024 * 1024);
  if (gib > scene.max_results_gib)
    throw InputError("Multibody/Output interval", "asks for " + base::number_text(rows) + " output rows, about " +
                                                    base::number_text(gib) + " GiB of results on disk; choose a longer interval, or raise Output/Maximum results "
                                                    "size (" + base::number_text(scene.max_results_gib) + " GiB)", scene.file);
  if (settings.rigid_reference && scene.probes.empty())
    throw InputError("Multibody/Rigid reference", "needs a probe: the deviation from the rigid run is measured at the "
                                                  "probes (Multibody/Probes)", scene.file);

  Vector<double> y, yp;
  multibody::InitialConditionReport report;
  {
    TimerOutput::Scope t(timer, "initial conditions");
    report = consistent_start(scene, y, yp);
  }
  std::cout << "  " << report.text();

  io::OutputFolder out(io::OutputFolder::choose(options.output_directory, scene.output_directory, options.file));
  out.tidy_previous_run("run");
  io::RunRecorder recorder(system, scene.probes, out, rows);
  io::ProbePaths paths(system, scene.probes); // kept in memory only for the rigid reference's deviation
  // The entries left "auto" are chosen here, for this scene, and said in the log and summary.json.
  multibody::IntegratorSettings integrator_settings = settings.integrator;
  const std::string chosen = multibody::choose_automatic_settings(system, integrator_settings);
  if (!chosen.empty() && integrator_settings.method != multibody::IntegrationMethod::generalized_alpha)
    std::cout << "  integrator (chosen for this scene): " << chosen << "\n";
  // Yardsticks of the residual maxima reported at the end (issue 25, item 12): what the
  // integrator was asked to hold, atol + rtol x the largest position coordinate at the start, and
  // the velocity tolerance of the frames and joints.
  double largest_coordinate = 0;
  for (unsigned int i = 0; i < system.n_q(); ++i) largest_coordinate = std::max(largest_coordinate, std::abs(y[i]));
  const double position_yardstick =
    integrator_settings.absolute_tolerance + integrator_settings.relative_tolerance * largest_coordinate;
  // 'auto' sets one tolerance per velocity (the modal ones scaled by their frequencies): the
  // yardstick is the largest of the frames' (the constraint rows measure frame velocities).
  double velocity_yardstick = 0;
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    for (unsigned int a = 0; a < std::min(6u, system.body(b).n_v()); ++a)
      velocity_yardstick = std::max(velocity_yardstick, integrator_settings.velocity_tolerance_of(system.v_offset(b) + a));
  if (velocity_yardstick == 0) velocity_yardstick = integrator_settings.absolute_tolerance;
  const auto owned_integrator = multibody::make_integrator(system, integrator_settings);
  auto &integrator = *owned_integrator;
  multibody::Monitors monitors(system);
  integrator.initialize(settings.start_time, y, yp);
  monitors.attach(integrator);
  const MonitorValues start = monitors.evaluate(settings.start_time, y);
  multibody::EnergyBalance balance(start);
  recorder.record(settings.start_time, y, start, balance.error(start));
  if (settings.rigid_reference) paths.record(settings.start_time, y);

  std::unique_ptr<io::AnimationWriter> animation;
  double next_frame = settings.start_time;
  const auto animate = [&](const double time, const Vector<double> &state) {
    if (!animation || time < next_frame - 1e-9 * scene.animation_interval) return;
    TimerOutput::Scope t(timer, "animation frames");
    animation->add_frame(time, state, out);
    while (next_frame <= time + 1e-9 * scene.animation_interval) next_frame += scene.animation_interval;
  };
  if (scene.animation_interval > 0)
    {
      animation = std::make_unique<io::AnimationWriter>(system);
      std::cout << "  animation every " << scene.animation_interval << " s (cell data 'body' numbers the bodies; "
                << "point-like bodies drawn at least " << std::setprecision(3) << animation->smallest_side()
                << " m wide):\n"
                << animation->description();
    }
  animate(settings.start_time, y);

  ProgressReport progress(settings.start_time, settings.end_time);
  std::string failure;
  // Ctrl-C / SIGTERM stop the integration at its next output row; the rows so far are written.
  base::watch_interrupts();
  {
    TimerOutput::Scope t(timer, "time integration");
    failure = integrate(system, integrator, settings, [&](const double time, const Vector<double> &state) {
      const MonitorValues m = monitors.evaluate(time, state);
      recorder.record(time, state, m, balance.error(m));
      if (settings.rigid_reference) paths.record(time, state);
      animate(time, state);
      progress.update(time, integrator.statistics().steps);
    });
  }
  progress.finish();

  std::optional<io::PathDeviation> deviation;
  const int signal = base::interrupted();
  base::stop_watching_interrupts();
  std::string reference_failure;
  if (settings.rigid_reference && failure.empty())
    {
      TimerOutput::Scope t(timer, "rigid reference run");
      std::cout << "  rigid reference: the same scene with every body rigid" << std::endl;
      deviation = rigid_reference_deviation(file, paths, timer, reference_failure);
      if (!reference_failure.empty())
        std::cout << "  warning: the rigid reference run failed (" << reference_failure << "); deviation over its "
                  << deviation->n_rows() << " output rows only\n";
      for (const auto &m : deviation->largest())
        std::cout << "  probe " << m.probe << ": largest deviation from the rigid path " << std::setprecision(4)
                  << 1e3 * m.distance << " mm at t = " << m.time << " s" << std::endl;
    }

  {
    TimerOutput::Scope t(timer, "write results");
    recorder.finish();
    if (animation) animation->finish(out);
    if (deviation) out.will_add("deviation.png");
    if (scene.plots)
      {
        std::vector<std::string> probe_names;
        for (const auto &p : scene.probes) probe_names.push_back(p->name());
        out.add_text("run.gp", io::run_plot_script("flextrack run " + options.file, probe_names));
        out.will_add("run.png");
      }
    out.add_parameters(*scene.parameters);
    if (deviation) deviation->write(out);
  }
  {
    io::JsonObject drift;
    drift.add("position_residual", recorder.max_position_residual)
      .add("position_residual_yardstick", position_yardstick)
      .add("velocity_residual", recorder.max_velocity_residual)
      .add("velocity_residual_yardstick", velocity_yardstick)
      .add("euler_parameter_normalisation", recorder.max_normalisation_drift)
      .add("relative_energy_balance_error", balance.largest_relative_to_run_scale());
    io::JsonObject summary;
    summary.add("program", "flextrack " FLEXTRACK_VERSION)
      .add("command", "run")
      .add("parameter_file", options.file)
      .add("set_on_command_line", io::override_texts(options.overrides))
      .add("notes", scene.notes)
      .add("status", signal ? "interrupted" : failure.empty() ? "completed" : "failed")
      .add("failure", failure)
      .add("start_time_s", settings.start_time)
      .add("end_time_s", settings.end_time)
      .add("time_reached_s", recorder.last_time())
      .add("output_rows", recorder.n_rows())
      .add("animation_frames", animation ? animation->n_frames() : 0u)
      .add("unknowns", system.size())
      .add("modes_per_body", [&] {
        io::JsonObject modes; // elastic coordinates of each body (0: rigid), e.g. for a study's table
        for (unsigned int b = 1; b < system.n_bodies(); ++b) modes.add(system.body(b).name(), system.body(b).n_modes());
        return modes;
      }())
      .add("integrator", statistics_json(integrator.statistics(), system)
                             .add("method", integrator_settings.method_name())
                             .add("maximum_order", integrator_settings.max_order)
                             .add("chosen_for_this_scene", chosen))
      .add("initial_conditions", initial_conditions_json(report))
      .add("max_over_output_rows", drift);
    if (settings.rigid_reference)
      {
        io::JsonObject reference;
        reference.add("status", deviation ? (reference_failure.empty() ? "completed" : "failed") : "skipped: the run failed")
          .add("failure", reference_failure)
          .add("rows_compared", deviation ? deviation->n_rows() : 0u)
          .raw("largest_deviation", deviation ? deviation->json(6) : "[]");
        summary.add("rigid_reference", reference);
      }
    summary
      .add("wall_time_s", io::timings_json(timer))
      .add("total_wall_time_s", clock.total_for_summary())
      .add("peak_memory_MiB", io::peak_memory_mib())
      .raw("parameters", io::parameters_as_json(*scene.parameters));
    out.add_summary(summary);
  }
  out.commit();
  // gnuplot runs in the output folder from an argument vector: no shell sees the folder's name.
  std::string plots; // the PNGs drawn, for the list of results
  for (const auto &[wanted, name] : {std::make_pair(deviation.has_value(), std::string("deviation")),
                                     std::make_pair(scene.plots, std::string("run"))})
    if (wanted && io::is_first_process())
      {
        const io::PlotResult plot = io::draw_png(out.path(), name + ".gp", name + ".png");
        if (plot.drawn) plots += ", " + name + ".png";
        else std::cout << "  warning: no " << name << ".png: " << plot.problem << " (" << name << ".gp draws it)\n";
      }

  const auto stats = integrator.statistics();
  std::cout << "  " << stats.steps << " steps (" << stats.error_test_failures << " rejected by the error test, "
            << stats.nonlinear_convergence_failures << " by Newton), " << stats.residual_evaluations << " residuals, "
            << stats.jacobian_evaluations << " Jacobians (" << stats.newton_restarts
            << " of them where Newton did not converge with an older one and solved the step again)";
  if (stats.condensed_factorizations > 0)
    std::cout << ", " << stats.condensed_factorizations << " of " << stats.factorizations
              << " factorisations with the positions condensed out (an LU of " << stats.condensed_unknowns << " of the "
              << system.size() << " unknowns)";
  std::cout << "\n  largest over the output rows: |Phi| " << std::setprecision(3)
            << recorder.max_position_residual << " m or rad (position tolerance " << position_yardstick
            << " m = atol + rtol x largest coordinate), |dPhi/dt| " << recorder.max_velocity_residual
            << " m/s or rad/s (velocity tolerance of the frames " << velocity_yardstick << "), ||p|-1| "
            << recorder.max_normalisation_drift << ", energy balance error " << balance.largest_relative_to_run_scale()
            << " of the run's energy scale (its largest |kinetic| or |potential| energy or |work|)\n";
  print_step_limiters(stats, system);
  print_timings(clock);
  const std::string rows_kept = ". The " + std::to_string(recorder.n_rows()) + " output rows up to t = " +
                                std::to_string(recorder.last_time()) + " s are in " + out.path() + "/";
  if (signal) throw base::Interrupted(signal, failure + rows_kept);
  if (!failure.empty()) throw SolverError(failure + rows_kept);
  std::cout << "  results in " << out.path() << "/ (" << (scene.probes.empty() ? "" : "probes.csv, ")
            << "monitors.csv, results.h5, summary.json, parameters_used.prm"
            << (animation ? ", animation.pvd" : "") << (deviation ? ", deviation.csv" : "")
            << plots << ")" << std::endl;
  return 0;
}
} // namespace flextrack::app
