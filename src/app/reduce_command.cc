// flextrack reduce: build a flexible body's FE model, reduce it (component mode synthesis),
// compute its inertia invariants and mode fields, and write the reduced body file. The file is
// cached: when the output folder already holds a reduced body whose input hash equals this
// scene's (every parameter but Output, and every file a parameter names), it is loaded and
// nothing is recomputed. flextrack inspect: print what a reduced body file holds.
#include <app/command_support.h>
#include <app/commands.h>
#include <fem/body_model.h>
#include <geometry/section_frame.h>
#include <io/body_export.h>
#include <io/body_scene.h>
#include <base/input_error.h>
#include <io/reduced_body_file.h>
#include <reduction/component_modes.h>
#include <reduction/reduced_body_builder.h>

#include <deal.II/base/timer.h>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace flextrack::app
{
using namespace dealii;
namespace fs = std::filesystem;

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

int reduce(const Options &options)
{
  Timer wall;
  std::ostringstream log;
  TimerOutput timer(log, TimerOutput::never, TimerOutput::wall_times);
  io::BodyScene scene;
  {
    TimerOutput::Scope t(timer, "read parameters and geometry");
    try
      {
        scene = io::read_body_scene(options.file);
      }
    catch (const geometry::FrameError &e)
      {
        throw InputError("Arm */Section frame/Kind", e.what(), options.file);
      }
  }
  const std::string dir = output_directory(options.output_directory, scene.output.directory, options.file);
  const std::string file = dir + "/reduced_body.h5";
  std::cout << "flextrack reduce: " << options.file << " (input hash " << scene.input_hash << ")" << std::endl;

  // The cache: an existing file with the same input hash is the result.
  reduction::ReducedBody body;
  bool cached = false;
  io::JsonObject check; // accuracy against the full model, when asked for
  if (fs::exists(file))
    {
      TimerOutput::Scope t(timer, "load cached reduced body");
      try
        {
          auto existing = io::read_reduced_body(file);
          if (existing.input_hash == scene.input_hash)
            {
              body = std::move(existing);
              cached = true;
            }
          else
            std::cout << "  inputs changed since " << file << " was written (hash " << existing.input_hash
                      << "): recomputing" << std::endl;
        }
      catch (const InputError &e)
        {
          std::cout << "  the existing " << file << " is unusable (" << e.message() << "): recomputing" << std::endl;
        }
    }
  if (cached)
    std::cout << "  reduced body is up to date: loaded " << file << " (same input hash), nothing recomputed" << std::endl;
  else
    {
      try
        {
          std::unique_ptr<fem::BodyModel> model;
          {
            TimerOutput::Scope t(timer, "assemble body (K, M, ties)");
            model = std::make_unique<fem::BodyModel>(scene.body);
          }
          std::cout << "  body: " << model->n_full_dofs() << " dofs, " << model->n_dofs() << " after ties and supports ("
                    << (model->is_supported() ? "supported" : "free") << ")" << std::endl;
          reduction::ReducedBasis basis;
          {
            TimerOutput::Scope t(timer, "reduce (eigen and static solves)");
            basis = reduction::reduce(*model, scene.reduction);
          }
          std::cout << "  reduction steps [s]:";
          for (const auto &[name, seconds] : basis.timings) std::cout << "  " << name << " " << std::setprecision(3) << seconds << ";";
          std::cout << std::endl;
          {
            TimerOutput::Scope t(timer, "invariants, mode fields, drawing");
            body = reduction::make_reduced_body(*model, basis, scene.reduction.method_name());
          }
          if (const unsigned int n = scene.reduction.n_check_modes; n > 0)
            {
              Timer full_timer;
              const auto full = reduction::full_model_frequencies_hz(*model, scene.reduction, n);
              const double full_time = full_timer.wall_time();
              double worst = 0;
              const auto reduced = basis.frequencies_hz();
              for (unsigned int k = 0; k < full.size() && k < reduced.size(); ++k)
                worst = std::max(worst, std::abs(reduced[k] - full[k]) / std::abs(full[k]));
              std::cout << "  check against the full model: " << full.size() << " lowest frequencies, largest relative "
                        << "difference " << std::setprecision(3) << worst << " (full eigen solve " << full_time << " s)"
                        << std::endl;
              check.add("modes", static_cast<unsigned int>(full.size()))
                .add("max_relative_frequency_difference", worst)
                .add("full_model_frequencies_Hz", full)
                .add("full_model_eigen_solve_wall_time_s", full_time);
            }
        }
      catch (const geometry::FrameError &e)
        {
          throw InputError("Arm */Section frame/Kind", e.what(), options.file);
        }
      catch (const InputError &e)
        {
          throw e.file().empty() ? e.in_file(options.file) : e;
        }
      body.input_hash = scene.input_hash;
      body.source = options.file;
      TimerOutput::Scope t(timer, "write output");
      make_directory(dir);
      io::write_reduced_body(body, file);
    }

  // Text results and exports (also after a cache hit: they describe this run).
  make_directory(dir);
  std::vector<std::string> exported;
  for (const auto &format : scene.output.export_formats)
    for (const auto &f : io::export_reduced_body(body, format, dir, "reduced_body", "Output/Export formats"))
      exported.push_back(f);
  std::ostringstream csv;
  csv << "mode,frequency_Hz\n";
  for (std::size_t k = 0; k < body.frequencies_hz.size(); ++k) csv << k + 1 << "," << csv_number(body.frequencies_hz[k]) << "\n";
  write_text(dir + "/frequencies.csv", csv.str());
  std::ostringstream used;
  scene.parameters->print_parameters(used, ParameterHandler::OutputStyle(ParameterHandler::PRM | ParameterHandler::Short));
  write_text(dir + "/parameters_used.prm", used.str());
  io::JsonObject summary;
  summary.add("program", "flextrack " FLEXTRACK_VERSION)
    .add("command", "reduce")
    .add("parameter_file", options.file)
    .add("reduced_body_file", file)
    .add("input_hash", scene.input_hash)
    .raw("loaded_from_cache", cached ? "true" : "false")
    .add("method", body.method)
    .add("body_degrees_of_freedom", body.n_body_dofs)
    .add("modes", body.n_modes())
    .add("frequencies_Hz", body.frequencies_hz)
    .add("mass_kg", body.invariants.mass)
    .raw("check_against_full_model", cached || scene.reduction.n_check_modes == 0 ? "null" : check.str(4))
    .add("wall_time_s", timings_json(timer))
    .add("total_wall_time_s", wall.wall_time())
    .add("peak_memory_MiB", peak_memory_mib())
    .raw("parameters", parameters_as_json(*scene.parameters));
  write_text(dir + "/summary.json", summary.str() + "\n");

  print_reduced_body(body);
  std::cout << "\n  wall time [s]:";
  for (const auto &[name, seconds] : timer.get_summary_data(TimerOutput::total_wall_time))
    std::cout << "  " << name << " " << std::setprecision(3) << seconds << ";";
  std::cout << "  total " << wall.wall_time() << "\n  peak memory: " << std::setprecision(4) << peak_memory_mib()
            << " MiB\n  results in " << dir << "/ (reduced_body.h5, frequencies.csv, summary.json";
  for (const auto &f : exported) std::cout << ", " << fs::path(f).filename().string();
  std::cout << ")" << std::endl;
  return 0;
}

int inspect(const Options &options)
{
  const auto body = io::read_reduced_body(options.file);
  std::cout << "flextrack inspect: " << options.file << "\n  written from " << body.source << " (input hash "
            << body.input_hash << ")\n";
  print_reduced_body(body);
  return 0;
}
} // namespace flextrack::app
