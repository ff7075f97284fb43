// flextrack bench: work-precision of the time integrators on one multibody scene (issue 11).
// A reference run (Radau IIA at rtol 1e-11; if that fails, IDA at rtol 1e-11, then 1e-10), then
// IDA and Radau IIA at rtol 1e-3 ... 1e-10 and
// generalised-alpha at steps (t_end - t0) / 50 ... / 6400, all on the scene's own bodies (its
// bases: the basis error is not part of these errors). The error of a run is, per probe, the
// largest distance of its path from the reference's at the output times [m]; the relative error
// divides by the extent of the reference path (the largest range of one coordinate), so a tip
// deflection probed in its body's frame is compared with its own size. Each run is a new system
// read from the scene (bodies from the reduced-body cache), timed over its integration only.
// Writes bench.csv (settings and reference in its header), bench.gp and bench.png (error against
// wall time, log-log) and summary.json (the fastest run of each method under relative errors
// 1e-3 and 1e-6).
#include <app/commands.h>
#include <app/multibody_runs.h>
#include <base/input_error.h>
#include <base/solver_error.h>
#include <io/gnuplot.h>
#include <io/multibody_scene.h>
#include <io/output_folder.h>
#include <io/path_deviation.h>

#include <deal.II/base/timer.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

namespace flextrack::app
{
using namespace dealii;

namespace
{
/// The reference runs, the first that completes. Radau IIA first: of order 5, its runs at rtol
/// 1e-7 ... 1e-10 on the slewing beam all stood 6.6e-8 of the tip path from IDA's at 1e-11, so
/// that IDA reference's own error (IDA at 1e-10: 2.4e-7) hid every error below it and made
/// Radau's error look flat there.
struct ReferenceSetting
{
  multibody::IntegrationMethod method;
  double rtol;
  const char *name;
};
const ReferenceSetting reference_settings[] = {{multibody::IntegrationMethod::radau, 1e-11, "Radau IIA"},
                                               {multibody::IntegrationMethod::ida, 1e-11, "IDA"},
                                               {multibody::IntegrationMethod::ida, 1e-10, "IDA"}};
/// A probe whose reference path spans less than this [m] does not move.
constexpr double still_probe_extent = 1e-9;

/// One run of the sweep: its settings and what it cost and achieved.
struct BenchRow
{
  std::string method, setting; ///< "ida", "rtol 1e-05" / "generalized_alpha", "step 0.01 s"
  double value = 0;            ///< rtol [-] or step [s]
  std::string failure;         ///< empty: reached the end time
  std::vector<double> errors;  ///< per probe [m]; NaN where the run did not reach the reference rows
  double max_relative = std::numeric_limits<double>::quiet_NaN();
  double wall = 0;             ///< integration wall time [s]
  multibody::IntegratorStatistics statistics;
  double peak_memory_mib = 0; ///< the process' peak resident memory during this run
};

/// Resets the kernel's peak-RSS mark of this process (Linux: clear_refs 5), so VmHWM measures one
/// run; false where that is not possible (then the peak is the process' so far).
bool reset_peak_memory()
{
  std::ofstream f("/proc/self/clear_refs");
  f << "5";
  return static_cast<bool>(f);
}

double peak_memory_mib()
{
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return io::peak_memory_mib();
}

/// Scales the scene's absolute tolerances with a new relative tolerance (their ratio kept).
multibody::IntegratorSettings with_rtol(const multibody::IntegratorSettings &scene, const double rtol)
{
  multibody::IntegratorSettings s = scene;
  s.method = multibody::IntegrationMethod::ida;
  s.automatic_method = false;
  const double scale = rtol / scene.relative_tolerance;
  s.relative_tolerance = rtol;
  s.absolute_tolerance = scene.absolute_tolerance * scale;
  if (scene.velocity_tolerance > 0) s.velocity_tolerance = scene.velocity_tolerance * scale;
  for (double &v : s.velocity_tolerances) v *= scale;
  return s;
}

/// Runs the scene of @p file with @p integrator settings, recording its probe paths.
BenchRow run_once(const io::SceneFile &file, const multibody::IntegratorSettings &integrator, TimerOutput &timer,
                  std::unique_ptr<io::MultibodyScene> &scene_out, std::unique_ptr<io::ProbePaths> &paths_out)
{
  BenchRow row;
  std::ostringstream quiet;
  scene_out = std::make_unique<io::MultibodyScene>(io::read_multibody_scene(file, quiet, timer, start_mpi_for_reduction));
  io::MultibodyScene &scene = *scene_out;
  scene.settings.integrator = integrator;
  paths_out = std::make_unique<io::ProbePaths>(*scene.system, scene.probes);
  Vector<double> y, yp;
  consistent_start(scene, y, yp);
  reset_peak_memory();
  const auto owned = multibody::make_integrator(*scene.system, integrator);
  Timer clock;
  owned->initialize(scene.settings.start_time, y, yp);
  paths_out->record(scene.settings.start_time, y);
  row.failure = integrate(*scene.system, *owned, scene.settings,
                          [&](const double t, const Vector<double> &state) { paths_out->record(t, state); });
  row.wall = clock.wall_time();
  row.statistics = owned->statistics();
  row.peak_memory_mib = peak_memory_mib();
  return row;
}

/// The largest range of one coordinate of each probe's reference path [m] (at least 1e-12).
std::vector<double> path_extents(const io::ProbePaths &reference, const unsigned int n_probes)
{
  std::vector<double> extent(n_probes, 1e-12);
  for (unsigned int p = 0; p < n_probes; ++p)
    for (unsigned int a = 0; a < 3; ++a)
      {
        double lo = std::numeric_limits<double>::max(), hi = -lo;
        for (unsigned int r = 0; r < reference.n_rows(); ++r)
          lo = std::min(lo, reference.position(p, r)[a]), hi = std::max(hi, reference.position(p, r)[a]);
        if (reference.n_rows()) extent[p] = std::max(extent[p], hi - lo);
      }
  return extent;
}

std::string scientific(const double v, const int digits = 2)
{
  std::ostringstream s;
  s << std::setprecision(digits) << std::scientific << v;
  return s.str();
}
} // namespace

int bench_command(const Options &options, const io::SceneFile &file)
{
  CommandClock clock;
  if (file.model != "multibody")
    throw InputError("Model", "is '" + file.model + "': flextrack bench needs a multibody scene ('Model = multibody')",
                     file.name);
  std::cout << "flextrack bench: " << options.file << std::endl;
  std::unique_ptr<io::MultibodyScene> scene;
  std::unique_ptr<io::ProbePaths> reference;
  // The scene as written: read once for its settings and probes (and to reduce its bodies once).
  scene = std::make_unique<io::MultibodyScene>(io::read_multibody_scene(file, std::cout, clock.timer, start_mpi_for_reduction));
  if (scene->probes.empty())
    throw InputError("Multibody/Probes", "is empty: flextrack bench measures the error at the probes", file.name);
  const multibody::IntegratorSettings base = scene->settings.integrator;
  const double span = scene->settings.end_time - scene->settings.start_time;
  std::vector<std::string> probe_names;
  for (const auto &p : scene->probes) probe_names.push_back(p->name());
  const unsigned int n_probes = probe_names.size();
  io::OutputFolder out(io::OutputFolder::choose(options.output_directory, scene->output_directory, options.file));
  out.tidy_previous_run("bench");
  out.will_add("bench.png");

  // Reference
  double rtol_ref = 0;
  std::string reference_method, reference_failures;
  BenchRow ref_row;
  for (const ReferenceSetting &r : reference_settings)
    {
      multibody::IntegratorSettings setting = with_rtol(base, r.rtol);
      setting.method = r.method;
      ref_row = run_once(file, setting, clock.timer, scene, reference);
      rtol_ref = r.rtol, reference_method = r.name;
      if (ref_row.failure.empty()) break;
      std::cout << "  reference (" << r.name << ", rtol " << scientific(r.rtol, 0) << ") failed: " << ref_row.failure << std::endl;
      reference_failures += std::string(reference_failures.empty() ? "" : "; ") + r.name + " at rtol " +
                            scientific(r.rtol, 0) + ": " + ref_row.failure;
    }
  if (!ref_row.failure.empty())
    throw SolverError("every reference run failed (" + reference_failures +
                      "). A work-precision study needs a reference; try a shorter End time.");
  const std::vector<double> extent = path_extents(*reference, n_probes);
  // A probe that does not move (on the ground, or on a body held still) has no path to compare
  // errors with: its error is 0 for every run, which made every run "within 1e-6". Such probes
  // are reported but left out of the relative error; a scene with no moving probe is refused.
  std::vector<bool> moving(n_probes);
  std::string still;
  for (unsigned int p = 0; p < n_probes; ++p)
    if (!(moving[p] = extent[p] >= still_probe_extent)) still += (still.empty() ? "" : ", ") + probe_names[p];
  if (still.size() && std::none_of(moving.begin(), moving.end(), [](bool m) { return m; }))
    throw InputError("Multibody/Probes", "no probe moves more than 1e-9 m in the reference run (" + still +
                                           "): bench measures each run's error relative to the extent of a probe's "
                                           "path; add a probe on a moving body", file.name);
  if (!still.empty())
    std::cout << "  probes that do not move (left out of the relative error): " << still << std::endl;
  std::cout << "  reference: " << reference_method << " rtol " << scientific(rtol_ref, 0) << ", " << ref_row.statistics.steps << " steps, "
            << std::setprecision(3) << ref_row.wall << " s; probe path extents [m]:";
  for (unsigned int p = 0; p < n_probes; ++p) std::cout << " " << probe_names[p] << " " << scientific(extent[p], 3);
  std::cout << std::endl;
  std::unique_ptr<io::ProbePaths> reference_paths = std::move(reference);
  std::unique_ptr<io::MultibodyScene> reference_scene = std::move(scene); // the paths refer to its system

  // The sweep
  std::vector<std::pair<std::string, multibody::IntegratorSettings>> settings;
  for (const auto method : {multibody::IntegrationMethod::ida, multibody::IntegrationMethod::radau})
    for (int k = 3; k <= 10; ++k)
      {
        multibody::IntegratorSettings s = with_rtol(base, std::pow(10.0, -k));
        s.method = method;
        settings.emplace_back("rtol 1e-" + std::string(k < 10 ? "0" : "") + std::to_string(k), s);
      }
  for (int k = 0; k <= 7; ++k)
    {
      multibody::IntegratorSettings g = with_rtol(base, 1e-8); // Newton tolerance well below the step's error
      g.method = multibody::IntegrationMethod::generalized_alpha;
      g.adaptive_step = false;
      g.step = span / (50.0 * std::pow(2.0, k));
      g.max_newton_iterations = std::max(base.max_newton_iterations, 10u);
      std::ostringstream label;
      label << "step " << std::setprecision(4) << g.step << " s";
      settings.emplace_back(label.str(), g);
    }
  std::vector<BenchRow> rows;
  for (unsigned int i = 0; i < settings.size(); ++i)
    {
      std::unique_ptr<io::MultibodyScene> run_scene;
      std::unique_ptr<io::ProbePaths> paths;
      BenchRow row;
      try
        {
          row = run_once(file, settings[i].second, clock.timer, run_scene, paths);
        }
      catch (const SolverError &e) // e.g. initial conditions
        {
          row.failure = e.what();
        }
      row.method = settings[i].second.method_name();
      row.setting = settings[i].first;
      row.value = row.method == "generalized_alpha" ? settings[i].second.step : settings[i].second.relative_tolerance;
      row.errors.assign(n_probes, std::numeric_limits<double>::quiet_NaN());
      if (paths && paths->n_rows() == reference_paths->n_rows())
        {
          const io::PathDeviation d(*paths, *reference_paths);
          row.max_relative = 0;
          for (unsigned int p = 0; p < n_probes; ++p)
            {
              row.errors[p] = d.largest()[p].distance;
              if (moving[p]) row.max_relative = std::max(row.max_relative, row.errors[p] / extent[p]);
            }
        }
      std::cout << "  [" << i + 1 << "/" << settings.size() << "] " << std::left << std::setw(18) << row.method << std::setw(18)
                << row.setting << std::right;
      if (row.failure.empty())
        std::cout << "relative error " << scientific(row.max_relative) << ", " << std::setprecision(3) << std::fixed
                  << row.wall << std::defaultfloat << " s, " << row.statistics.steps << " steps" << std::endl;
      else
        std::cout << "failed: " << row.failure.substr(0, 160) << std::endl;
      rows.push_back(row);
    }

  // bench.csv
  std::ostringstream csv;
  csv << "# flextrack bench " << options.file << "\n"
      << "# reference: " << reference_method << " rtol " << scientific(rtol_ref, 0) << " (absolute tolerances scaled with rtol from the scene's), "
      << "the scene's bodies and bases; " << ref_row.statistics.steps << " steps, " << ref_row.wall << " s\n"
      << "# error_<probe>_m: largest distance of the probe's path from the reference's over the output times (every "
      << reference_scene->settings.output_interval << " s) [m]; max_relative_error: the largest of those divided by the "
      << "extent of the reference path (largest range of one coordinate):";
  for (unsigned int p = 0; p < n_probes; ++p) csv << " " << probe_names[p] << " " << extent[p] << " m";
  csv << "\n# IDA (ida) and Radau IIA (radau): absolute tolerances scaled with rtol; generalized_alpha: fixed step, rho_inf "
      << base.spectral_radius << ", Newton at rtol 1e-8; wall_time_s: integration only; peak memory: the process "
      << "during that run\n";
  csv << "method,setting,value,status,max_relative_error";
  for (const auto &n : probe_names) csv << ",error_" << n << "_m";
  csv << ",wall_time_s,steps,rejected_error_test,rejected_newton,newton_restarts,residual_evaluations,jacobian_evaluations,peak_memory_MiB\n";
  for (const auto &r : rows)
    {
      csv << r.method << "," << r.setting << "," << io::csv_number(r.value) << "," << (r.failure.empty() ? "completed" : "failed")
          << "," << io::csv_number(r.max_relative);
      for (const double e : r.errors) csv << "," << io::csv_number(e);
      csv << "," << io::csv_number(r.wall) << "," << r.statistics.steps << "," << r.statistics.error_test_failures << ","
          << r.statistics.nonlinear_convergence_failures << "," << r.statistics.newton_restarts << ","
          << r.statistics.residual_evaluations << ","
          << r.statistics.jacobian_evaluations << "," << io::csv_number(r.peak_memory_mib) << "\n";
    }
  out.add_text("bench.csv", csv.str());
  out.add_text("bench.gp", io::bench_plot_script("Work-precision: " + options.file, n_probes));

  // summary.json: the fastest run of each method under relative errors 1e-3 and 1e-6
  io::JsonObject summary;
  summary.add("program", "flextrack " FLEXTRACK_VERSION)
    .add("command", "bench")
    .add("parameter_file", options.file)
      .add("set_on_command_line", io::override_texts(options.overrides))
    .add("reference_method", reference_method)
    .add("reference_rtol", rtol_ref)
    .add("reference_steps", static_cast<double>(ref_row.statistics.steps))
    .add("reference_wall_time_s", ref_row.wall);
  std::cout << "  fastest runs:" << std::endl;
  for (const std::string method : {"ida", "radau", "generalized_alpha"})
    for (const double target : {1e-3, 1e-6})
      {
        const BenchRow *best = nullptr;
        for (const auto &r : rows)
          if (r.method == method && r.failure.empty() && r.max_relative <= target && (!best || r.wall < best->wall)) best = &r;
        const std::string key = method + "_fastest_under_" + scientific(target, 0);
        std::cout << "    " << method << ", relative error <= " << scientific(target, 0) << ": "
                  << (best ? best->setting + ", " + scientific(best->max_relative) + " in " + scientific(best->wall, 3) + " s"
                           : std::string("none in the sweep"))
                  << std::endl;
        summary.add(key, best ? best->setting : std::string("none"));
        summary.add(key + "_wall_time_s", best ? best->wall : std::numeric_limits<double>::quiet_NaN());
      }
  summary.add("total_wall_time_s", clock.total_for_summary());
  out.add_summary(summary);
  out.commit();
  const io::PlotResult plot = io::is_first_process() ? io::draw_png(out.path(), "bench.gp", "bench.png")
                                                     : io::PlotResult{false, "not the first process"};
  std::cout << "  results in " << out.path() << "/ (bench.csv, bench.gp" << (plot.drawn ? ", bench.png" : "")
            << ", summary.json)" << std::endl;
  if (!plot.drawn && io::is_first_process())
    std::cout << "  warning: no bench.png: " << plot.problem << " (bench.gp draws it)\n";
  return 0;
}
} // namespace flextrack::app
