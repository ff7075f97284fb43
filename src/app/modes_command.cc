// flextrack modes and flextrack converge: the natural modes of one arm or solid, once or on
// successively refined meshes. They follow the pipeline: read the scene (io), build the FE model
// (geometry, fem), solve the eigenproblem (reduction), write results (io). Nothing is written
// until every computation has succeeded, so a failed run leaves no half-written results behind.
#include <app/commands.h>
#include <base/input_error.h>
#include <fem/curved_beam_model.h>
#include <fem/load_case.h>
#include <fem/solid_model.h>
#include <io/arm_scene.h>
#include <io/body_scene.h>
#include <io/gnuplot.h>
#include <io/mode_shape_writer.h>
#include <io/output_folder.h>
#include <reduction/modal_participation.h>
#include <reduction/modal_solver.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/component_mask.h>

#include <deal.II/base/timer.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <iostream>
#include <sstream>
#include <type_traits>

namespace flextrack::app
{
using namespace dealii;
namespace fs = std::filesystem;

namespace
{
struct ModalRun
{
  unsigned int n_dofs = 0, n_free_dofs = 0, n_cells = 0;
  reduction::Modes modes;
};

/// Build the model on the given refinement level and solve for its lowest modes.
/// The FE model of the scene's structure, kept for output.
struct Model
{
  std::unique_ptr<fem::CurvedBeamModel> arm;
  std::unique_ptr<fem::SolidModel> solid;
};

/// The lowest modes of a built FE model (arm or solid), with the scene's file in any error. A
/// solid's K and M are released on the way (the eigen solve's memory is the factor's, M is
/// applied cell by cell): the model keeps its mesh, dofs and mass_operator() for output.
template <typename ModelType>
ModalRun solve(ModelType &model, const io::ArmScene &scene, TimerOutput &timer)
{
  ModalRun run;
  run.n_dofs = model.n_dofs();
  run.n_free_dofs = model.n_free_dofs();
  run.n_cells = model.n_cells();
  TimerOutput::Scope t(timer, "eigen solve");
  try
    {
      if constexpr (std::is_same_v<ModelType, fem::SolidModel>)
        run.modes = reduction::lowest_modes_releasing_matrices(model, scene.modal);
      else
        run.modes = reduction::lowest_modes(model, scene.modal);
    }
  catch (const InputError &e)
    {
      throw e.in_file(scene.file);
    }
  return run;
}

/// Build the scene's FE model on the given refinement level and solve for its lowest modes;
/// @p keep receives the model (for output).
ModalRun analyse(const io::ArmScene &scene, const unsigned int refinement, TimerOutput &timer, Model *keep = nullptr)
{
  Model model;
  {
    TimerOutput::Scope t(timer, "assemble K and M");
    try
      {
        if (scene.is_solid)
          model.solid = std::make_unique<fem::SolidModel>(scene.solid, refinement);
        else
          model.arm = std::make_unique<fem::CurvedBeamModel>(scene.arm, refinement);
      }
    catch (const InputError &e)
      {
        throw e.in_file(scene.file);
      }
  }
  const ModalRun run = model.solid ? solve(*model.solid, scene, timer) : solve(*model.arm, scene, timer);
  if (keep) *keep = std::move(model);
  return run;
}



/// The arm or solid scene of @p file, parsed into @p prm (kept for parameters_used.prm), timed.
io::ArmScene read_scene(const io::SceneFile &file, ParameterHandler &prm, TimerOutput &timer)
{
  TimerOutput::Scope t(timer, "read parameters and geometry");
  io::declare_arm_scene(prm);
  return io::read_arm_scene(file, prm);
}

/// An arm with every support free (the default since issue 25, item 5) is analysed free-free:
/// said, since a cantilever written for the old default now shows six rigid-body modes first.
std::string unsupported_arm_note(const io::ArmScene &scene)
{
  if (scene.is_solid) return "";
  for (const auto &s : scene.arm.supports)
    if (s.kind != fem::SupportKind::free) return "";
  return "  note: the arm has no support (Arm/Supports: every support free, the default), so it is analysed free-free: "
         "its first six modes are rigid-body motions at near-zero frequency. A cantilever says 'Arm/Supports/Start = "
         "clamped'\n";
}

std::string describe(const io::ArmScene &scene)
{
  std::ostringstream d;
  if (scene.is_solid)
    {
      const char *element[] = {"hex20", "hex8", "hex27"};
      d << "solid: " << scene.solid.mesh->source << ", " << scene.solid.mesh->triangulation.n_active_cells()
        << " cells, " << element[static_cast<int>(scene.solid.element)] << " elements, "
        << scene.solid.gauss_points << "^3 Gauss points";
    }
  else
    d << "arm: " << scene.arm.curve->description() << ", L = " << scene.arm.curve->length() << " m"
      << (scene.arm.curve->is_closed() ? " (closed)" : "") << ", " << scene.arm.n_elements
      << " elements of degree " << scene.arm.degree << "; supports: " << scene.arm.supports_text();
  return d.str();
}
/// Participation factors, effective masses and classes of the modes (one process only: the
/// matrices of a solid under mpirun are distributed).
struct Participation
{
  reduction::ModalParticipation masses;
  std::vector<reduction::ModeClass> classes;
  bool arm = false;
};

std::optional<Participation> participation(const Model &model, const reduction::Modes &modes,
                                           const reduction::ModalSettings &settings)
{
  if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1) return std::nullopt;
  const reduction::DofLayout layout = model.arm ? reduction::dof_layout(*model.arm) : reduction::dof_layout(*model.solid);
  // The assembled M where the model still has it (arms; solids whose eigen solve kept K and M),
  // else the solid's cell-by-cell product.
  const auto &assembled = model.arm ? model.arm->mass_matrix() : model.solid->mass_matrix();
  const reduction::MassProduct M =
    assembled.m() > 0 ? reduction::product_with(assembled)
              : reduction::MassProduct([&solid = *model.solid](const Vector<double> &x, Vector<double> &y) {
                  Assert(x.size() == solid.n_dofs() && y.size() == solid.n_dofs(),
                         ExcDimensionMismatch(x.size(), solid.n_dofs()));
                  solid.mass_operator().vmult(x.begin(), y.begin());
                });
  const Point<3> x_ref(settings.participation_reference[0], settings.participation_reference[1],
                       settings.participation_reference[2]);
  Participation p;
  p.masses = reduction::modal_participation(modes.shapes, M, layout, x_ref);
  p.classes = reduction::classify_modes(modes.shapes, M, layout, p.masses);
  p.arm = static_cast<bool>(model.arm);
  return p;
}

/// The table of effective masses, as CalculiX prints them: per mode the fraction of r_d^T M r_d
/// in x, y, z, rx, ry, rz, the cumulative fractions, the dominant direction and the mode's class.
void print_participation(const Participation &participation)
{
  const auto &p = participation.masses;
  std::cout << "\n  effective modal mass, fraction of the moving mass (x " << std::setprecision(6) << p.total_mass[0]
            << ", y " << p.total_mass[1] << ", z " << p.total_mass[2] << " kg)\n  and of its moment of inertia about "
            << "axes through x_ref = (" << p.reference_point << ") m (rx " << p.total_mass[3] << ", ry " << p.total_mass[4]
            << ", rz " << p.total_mass[5] << " kg m^2)\n"
            << "  mode      x      y      z     rx     ry     rz  sum x  sum y  sum z sum rx sum ry sum rz  dom"
            << (participation.arm ? "  class (kinetic energy share)" : "") << "\n";
  std::array<double, 6> sum{};
  for (std::size_t k = 0; k < p.effective_mass.size(); ++k)
    {
      std::cout << "  " << std::setw(4) << k + 1 << std::fixed << std::setprecision(4);
      for (unsigned int d = 0; d < 6; ++d)
        {
          sum[d] += p.fraction(k, d);
          std::cout << std::setw(7) << std::setprecision(4) << p.fraction(k, d);
        }
      for (unsigned int d = 0; d < 6; ++d) std::cout << std::setw(7) << std::setprecision(4) << sum[d];
      const unsigned int dominant = p.dominant_direction(k);
      std::string name = dominant < 6 ? reduction::rigid_direction_names[dominant] : "-";
      if (participation.arm) name.resize(3, ' ');
      std::cout << "  " << name;
      if (participation.arm)
        std::cout << "  " << participation.classes[k].kind << " (" << std::setprecision(3)
                  << participation.classes[k].share << ")";
      std::cout << "\n" << std::defaultfloat;
    }
}

std::string participation_json(const Participation &participation)
{
  const auto &p = participation.masses;
  io::JsonObject j;
  j.add("total_moving_mass_kg", std::vector<double>(p.total_mass.begin(), p.total_mass.begin() + 3))
    .add("reference_point_m", std::vector<double>{p.reference_point[0], p.reference_point[1], p.reference_point[2]})
    .add("total_moment_of_inertia_kg_m2", std::vector<double>(p.total_mass.begin() + 3, p.total_mass.end()));
  for (unsigned int d = 0; d < 6; ++d)
    {
      std::vector<double> gamma, fraction;
      for (std::size_t k = 0; k < p.factors.size(); ++k)
        {
          gamma.push_back(p.factors[k][d]);
          fraction.push_back(p.fraction(k, d));
        }
      const std::string axis = reduction::rigid_direction_names[d];
      j.add("participation_factor_" + axis + (d < 3 ? "_sqrt_kg" : "_sqrt_kg_m"), gamma)
        .add("effective_mass_fraction_" + axis, fraction);
    }
  std::string kind = "[";
  std::vector<double> share;
  for (const auto &c : participation.classes)
    {
      kind += (share.empty() ? "" : ", ") + io::JsonObject::quote(c.kind);
      share.push_back(c.share);
    }
  j.raw("mode_class", kind + "]").add(participation.arm ? "mode_class_energy_share" : "mode_class_effective_mass_fraction", share);
  return j.str(2);
}
} // namespace

int modes_command(const Options &options, const io::SceneFile &file)
{
  CommandClock clock;
  auto &timer = clock.timer;
  ParameterHandler prm;
  const io::ArmScene scene = read_scene(file, prm, timer);
  std::cout << "flextrack modes: " << options.file << "\n  " << describe(scene) << std::endl
            << unsupported_arm_note(scene);

  Model model;
  const ModalRun run = analyse(scene, 0, timer, &model);
  const std::vector<double> f = run.modes.frequencies_hz();
  const auto masses = participation(model, run.modes, scene.modal);

  // Every computation has succeeded: now write the results.
  io::OutputFolder out(io::OutputFolder::choose(options.output_directory, scene.output.directory, options.file));
  {
    TimerOutput::Scope t(timer, "write output");
    out.add_frequencies(f);
    out.add_parameters(prm);
    io::remove_mode_shapes(out.path());
    if (scene.output.mode_shapes && model.arm && io::is_first_process())
      io::write_mode_shapes<1>(out, model.arm->dof_handler(), model.arm->mapping(), run.modes.shapes,
                               scene.output.subdivisions);
    if (scene.output.mode_shapes && model.solid)
      io::write_mode_shapes<3>(out, model.solid->dof_handler(), model.solid->mapping(), run.modes.shapes,
                               std::min(scene.output.subdivisions, 2u));
  }
  io::JsonObject summary;
  summary.add("program", "flextrack " FLEXTRACK_VERSION)
    .add("command", "modes")
    .add("parameter_file", options.file)
      .add("set_on_command_line", io::override_texts(options.overrides))
    .add("model", describe(scene))
    .add("elements", run.n_cells)
    .add("degrees_of_freedom", run.n_dofs)
    .add("free_degrees_of_freedom", run.n_free_dofs)
    .add("mpi_processes", Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD))
    .add("frequencies_Hz", f)
    .add("eigenvalues_rad2_per_s2", run.modes.eigenvalues)
    .raw("modal_participation", masses ? participation_json(*masses) : "null")
    .add("wall_time_s", io::timings_json(timer))
    .add("total_wall_time_s", clock.total_for_summary())
    .add("peak_memory_MiB", io::peak_memory_mib())
    .raw("parameters", io::parameters_as_json(prm));
  out.add_summary(summary);
  out.commit();

  std::cout << "  degrees of freedom: " << run.n_dofs << " (" << run.n_free_dofs << " free)\n\n"
            << "  mode  frequency [Hz]\n";
  for (std::size_t k = 0; k < f.size(); ++k)
    std::cout << "  " << std::setw(4) << k + 1 << "  " << std::setprecision(10) << f[k] << "\n";
  if (masses) print_participation(*masses);
  print_timings(clock);
  std::cout << "  results in " << out.path() << "/ (frequencies.csv, summary.json"
            << (scene.output.mode_shapes ? ", mode_shapes.pvd" : "") << ")" << std::endl;
  return 0;
}

int converge_command(const Options &options, const io::SceneFile &file)
{
  CommandClock clock;
  auto &timer = clock.timer;
  ParameterHandler prm;
  const io::ArmScene scene = read_scene(file, prm, timer);
  const unsigned int K = options.refinements;
  // The finest level is checked before the first: a level that cannot fit must not be found
  // after an hour spent on the coarser ones.
  try
    {
      const std::string how = " after " + std::to_string(K) + " refinements (--refinements)";
      if (scene.is_solid)
        fem::check_solid_cell_count(double(scene.solid.mesh->triangulation.n_active_cells()) * std::pow(8.0, K),
                                    scene.solid.element, "Solid/Mesh" + how);
      else
        fem::check_arm_cell_count(scene.arm, std::ldexp(scene.arm.n_elements, K), how);
    }
  catch (const InputError &e)
    {
      throw e.in_file(options.file);
    }
  std::cout << "flextrack converge: " << options.file << ", " << K << " refinements of\n  " << describe(scene)
            << std::endl
            << unsupported_arm_note(scene);

  std::vector<ModalRun> levels;
  std::vector<double> level_times;
  for (unsigned int k = 0; k <= K; ++k)
    {
      Timer level_timer;
      levels.push_back(analyse(scene, k, timer));
      level_times.push_back(level_timer.wall_time());
      std::cout << "  level " << k << ": " << levels.back().n_cells << " elements, " << levels.back().n_dofs
                << " dofs, " << std::setprecision(3) << level_times.back() << " s" << std::endl;
    }

  // Per mode and level: frequency, change from the previous level, observed order
  // p = log2(change_{k-1} / change_k) (halving h), and the error against the finest level.
  const unsigned int n_modes = scene.modal.n_modes;
  std::vector<std::vector<double>> f(levels.size());
  for (unsigned int k = 0; k <= K; ++k) f[k] = levels[k].modes.frequencies_hz();
  std::ostringstream csv;
  csv << "mode,level,elements,dofs,frequency_Hz,change_Hz,observed_order,relative_error_vs_finest,wall_time_s\n";
  std::cout << "\n  mode level     dofs      frequency [Hz]     change [Hz]   order\n";
  for (unsigned int m = 0; m < n_modes; ++m)
    for (unsigned int k = 0; k <= K; ++k)
      {
        const double fk = f[k][m];
        const double finest = f[K][m];
        const double change = k > 0 ? fk - f[k - 1][m] : NAN;
        double order = NAN;
        if (k > 1)
          {
            const double previous = f[k - 1][m] - f[k - 2][m];
            order = std::log2(std::abs(previous / change));
          }
        const double error = k < K ? std::abs(fk - finest) / std::abs(finest) : NAN;
        auto field = [](double v) { return std::isnan(v) ? std::string() : io::csv_number(v); };
        csv << m + 1 << "," << k << "," << levels[k].n_cells << "," << levels[k].n_dofs << "," << io::csv_number(fk) << ","
            << field(change) << "," << field(order) << "," << field(error) << "," << io::csv_number(level_times[k]) << "\n";
        std::ostringstream row;
        row << std::setw(6) << m + 1 << std::setw(6) << k << std::setw(9) << levels[k].n_dofs << std::setw(20)
            << std::setprecision(12) << fk << std::setw(16) << std::setprecision(3) << std::scientific;
        if (std::isnan(change)) row << "-"; else row << change;
        row << std::setw(8) << std::fixed << std::setprecision(2);
        if (std::isnan(order)) row << "-"; else row << order;
        std::cout << row.str() << "\n";
      }

  io::OutputFolder out(io::OutputFolder::choose(options.output_directory, scene.output.directory, options.file));
  out.tidy_previous_run("converge");
  out.will_add("convergence.png");
  out.add_text("convergence.csv", csv.str());
  // Plot: relative error against the finest level versus dofs, log-log, one line per mode.
  out.add_text("convergence.gp", io::convergence_plot_script("Mesh convergence: " + describe(scene), n_modes));

  io::JsonObject summary;
  summary.add("program", "flextrack " FLEXTRACK_VERSION)
    .add("command", "converge")
    .add("parameter_file", options.file)
      .add("set_on_command_line", io::override_texts(options.overrides))
    .add("refinements", K);
  std::string level_list = "[";
  for (unsigned int k = 0; k <= K; ++k)
    {
      io::JsonObject l;
      l.add("level", k).add("elements", levels[k].n_cells).add("degrees_of_freedom", levels[k].n_dofs)
        .add("frequencies_Hz", f[k]).add("wall_time_s", level_times[k]);
      level_list += (k ? ", " : "") + l.str(4);
    }
  summary.raw("levels", level_list + "]")
    .add("wall_time_s", io::timings_json(timer))
    .add("total_wall_time_s", clock.total_for_summary())
    .add("peak_memory_MiB", io::peak_memory_mib())
    .raw("parameters", io::parameters_as_json(prm));
  out.add_summary(summary);
  out.commit();
  // gnuplot runs in the output folder from an argument vector: no shell sees the folder's name.
  const io::PlotResult plot = io::is_first_process() ? io::draw_png(out.path(), "convergence.gp", "convergence.png")
                                                     : io::PlotResult{false, "not the first process"};
  std::cout << "\n  results in " << out.path() << "/ (convergence.csv, summary.json"
            << (plot.drawn ? ", convergence.png" : "; no plot: " + plot.problem) << ")\n  total wall time "
            << clock.wall.wall_time() << " s" << std::endl;
  return 0;
}

int print_parameters_command()
{
  // Every scene kind: "Model", "Arm" (arm scenes), "Solid", and a body with one arm called NAME.
  ParameterHandler prm;
  io::declare_body_scene(prm, {"NAME"});
  fem::Arm::declare_parameters(prm);
  fem::StaticSettings::declare_parameters(prm);
  fem::LoadCase::declare_parameters(prm, {"NAME"});
  prm.print_parameters(std::cout, ParameterHandler::PRM);
  return 0;
}
} // namespace flextrack::app
