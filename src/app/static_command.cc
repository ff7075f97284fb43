// flextrack static: the linear static solution of an arm or solid scene's full FE model under
// each of its load cases (Static/Load cases, fem/load_case.h).
//
// Arms are meshed with a node at every point load, line-load end and report point (they are
// added to the mesh as 'free' supports), so point loads are nodal and the reported values are
// nodal values. Solids take node set forces (a uniform traction on the set's faces), node set
// moments and gravity, and report the mean displacement and best-fit rotation of node sets. The stiffness is assembled once without
// supports and factorised once with them (reduction/static_solver.h, CHOLMOD); every load case
// is then one forward/backward solve. Reported per case: the displacements at the report points,
// the support reactions and their resultant against the resultant of the applied loads
// (equilibrium), and the strain energy. Nothing is written until every case is solved.
//
// A body scene ('Model = body') is solved twice per case (reduction/body_statics.h): with the
// full FE model and with the reduced body of its Reduction settings (K_r eta = Phi^T f), and the
// relative difference is printed at every report place: how good the basis is for that load.
#include <app/commands.h>
#include <base/input_error.h>
#include <fem/curved_beam_model.h>
#include <fem/load_case.h>
#include <fem/solid_loads.h>
#include <fem/solid_model.h>
#include <io/arm_scene.h>
#include <io/body_scene.h>
#include <io/output_folder.h>
#include <io/static_field_writer.h>
#include <reduction/body_statics.h>
#include <reduction/static_solver.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>

#include <functional>
#include <iomanip>
#include <memory>
#include <iostream>
#include <sstream>

namespace flextrack::app
{
using namespace dealii;

namespace
{
/// The results of one load case: values at the report points (an arm: u and theta [m, rad] at an
/// arc length; a solid: the mean u [m] of a node set).
struct CaseResult
{
  std::string name;
  std::vector<std::vector<double>> values;
  fem::Resultant applied, reactions; ///< about the origin [N], [N m]
  double strain_energy = 0, residual = 0;
};

/// What every load case reports: the points (labels for the log, leading CSV fields) and the
/// CSV header.
struct Report
{
  std::string csv_header;
  std::vector<std::string> labels, csv_fields;
  std::vector<CaseResult> cases;
  unsigned int n_cells = 0, n_dofs = 0, n_free_dofs = 0;
  std::string description;
  /// Writes the fields of every case (VTU, and the arm's section_forces.csv) into the folder.
  std::function<void(io::OutputFolder &)> write_fields;
  std::string files; ///< what write_fields writes, for the last line of the log
  std::string solver;
  unsigned int cg_iterations = 0;
};

/// section_forces.csv of an arm: per case the section forces along s (fem::SectionForces).
std::string section_force_table(const fem::CurvedBeamModel &model, const std::vector<std::string> &names,
                                const std::vector<reduction::StaticSolution> &solutions)
{
  std::ostringstream csv;
  csv << "load_case,s_m,N_N,Q_y_N,Q_z_N,T_Nm,M_y_Nm,M_z_Nm\n";
  for (std::size_t i = 0; i < names.size(); ++i)
    for (const auto &f : model.section_forces(solutions[i].u))
      {
        csv << names[i] << "," << io::csv_number(f.s);
        for (const double v : f.values) csv << "," << io::csv_number(v);
        csv << "\n";
      }
  return csv.str();
}

std::vector<std::string> case_names(const io::ArmScene &scene)
{
  std::vector<std::string> names;
  for (const auto &c : scene.load_cases) names.push_back(c.name);
  return names;
}

std::vector<Vector<double>> displacements(const std::vector<reduction::StaticSolution> &solutions)
{
  std::vector<Vector<double>> u;
  for (const auto &s : solutions) u.push_back(s.u);
  return u;
}

std::string vector_text(const Tensor<1, 3> &v, const int precision = 6)
{
  std::ostringstream o;
  o << std::setprecision(precision) << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
  return o.str();
}

std::string values_text(const std::vector<double> &v)
{
  std::ostringstream o;
  o << std::setprecision(10) << "u = (" << v[0] << ", " << v[1] << ", " << v[2] << ") m";
  if (v.size() == 6) o << ",  theta = (" << v[3] << ", " << v[4] << ", " << v[5] << ") rad";
  return o.str();
}

std::vector<double> as_list(const Tensor<1, 3> &v) { return {v[0], v[1], v[2]}; }

void print_case(const CaseResult &r, const Report &report)
{
  std::cout << "\n  load case " << r.name << "\n";
  for (std::size_t k = 0; k < report.labels.size(); ++k)
    std::cout << "    " << report.labels[k] << ":  " << values_text(r.values[k]) << "\n";
  std::cout << "    applied loads:  F = " << vector_text(r.applied.force) << " N,  M = " << vector_text(r.applied.moment)
            << " N m (about the origin)\n"
            << "    reactions:      F = " << vector_text(r.reactions.force) << " N,  M = "
            << vector_text(r.reactions.moment) << " N m\n"
            << std::scientific << std::setprecision(2) << "    equilibrium:    |F + R| = "
            << (r.applied.force + r.reactions.force).norm() << " N,  |M + M_R| = "
            << (r.applied.moment + r.reactions.moment).norm() << " N m;  relative residual of K u = f "
            << r.residual << "\n"
            << std::defaultfloat << std::setprecision(10) << "    strain energy:  " << r.strain_energy << " J\n";
}

std::string csv_table(const Report &report)
{
  std::ostringstream csv;
  csv << report.csv_header << "\n";
  for (const auto &r : report.cases)
    for (std::size_t k = 0; k < report.labels.size(); ++k)
      {
        csv << r.name << "," << report.csv_fields[k];
        for (const double v : r.values[k]) csv << "," << io::csv_number(v);
        csv << "\n";
      }
  return csv.str();
}

std::string cases_json(const Report &report)
{
  std::string list = "[";
  for (std::size_t i = 0; i < report.cases.size(); ++i)
    {
      const auto &r = report.cases[i];
      std::string at = "[";
      for (std::size_t k = 0; k < report.labels.size(); ++k)
        {
          io::JsonObject p;
          p.add("at", report.labels[k]).add("values", r.values[k]);
          at += (k ? ", " : "") + p.str(6);
        }
      io::JsonObject c;
      c.add("name", r.name)
        .raw("points", at + "]")
        .add("applied_force_N", as_list(r.applied.force))
        .add("applied_moment_Nm", as_list(r.applied.moment))
        .add("reaction_force_N", as_list(r.reactions.force))
        .add("reaction_moment_Nm", as_list(r.reactions.moment))
        .add("force_imbalance_N", (r.applied.force + r.reactions.force).norm())
        .add("moment_imbalance_Nm", (r.applied.moment + r.reactions.moment).norm())
        .add("relative_residual", r.residual)
        .add("strain_energy_J", r.strain_energy);
      list += (i ? ", " : "") + c.str(4);
    }
  return list + "]";
}

/// Solves every load case on @p model and fills the common parts of the cases; the nodal load
/// vectors are left in @p loads.
template <typename Model>
std::vector<reduction::StaticSolution> solve_cases(const Model &model, const io::ArmScene &scene, Report &report,
                                                   TimerOutput &timer, std::vector<Vector<double>> &loads,
                                                   reduction::StaticSolverSettings settings = {})
{
  std::vector<Vector<double>> settlements;
  {
    TimerOutput::Scope t(timer, "assemble loads");
    for (const auto &c : scene.load_cases)
      {
        loads.push_back(model.load_vector(c));
        settlements.push_back(model.support_displacements(c));
      }
  }
  report.n_cells = model.n_cells();
  report.n_dofs = model.n_dofs();
  report.n_free_dofs = model.n_free_dofs();
  std::cout << "flextrack static: " << scene.file << "\n  " << report.description << ", " << report.n_dofs << " dofs ("
            << report.n_free_dofs << " free), " << loads.size() << " load case" << (loads.size() == 1 ? "" : "s")
            << std::endl;
  TimerOutput::Scope t(timer, settings.iterative ? "multigrid and CG solves" : "factorise and solve");
  report.solver = settings.iterative ? "iterative (CG + algebraic multigrid)" : "direct (CHOLMOD)";
  const reduction::StaticSolver solver(model.stiffness_matrix(), model.constraints(), std::move(settings));
  const auto solutions = solver.solve(loads, settlements);
  report.cg_iterations = solver.iterations();
  if (report.cg_iterations > 0)
    std::cout << "  conjugate gradients: " << report.cg_iterations << " iterations for " << loads.size()
              << " load case" << (loads.size() == 1 ? "" : "s") << std::endl;
  for (std::size_t i = 0; i < solutions.size(); ++i)
    {
      CaseResult r;
      r.name = scene.load_cases[i].name;
      r.strain_energy = solutions[i].strain_energy;
      r.residual = solutions[i].residual;
      report.cases.push_back(r);
    }
  return solutions;
}

Report arm_statics(const io::ArmScene &scene, TimerOutput &timer)
{
  Report report;
  const std::vector<double> points =
    scene.statics.points.empty() ? std::vector<double>{scene.arm.curve->length()} : scene.statics.points;
  // Shared with report.write_fields, which draws the solutions after every case is solved.
  const auto meshed = std::make_shared<const fem::Arm>(fem::with_load_stations(scene.arm, scene.load_cases, points));
  const fem::Arm &arm = *meshed;
  std::shared_ptr<const fem::CurvedBeamModel> model;
  {
    TimerOutput::Scope t(timer, "assemble K");
    model = std::make_shared<const fem::CurvedBeamModel>(arm, 0, false);
  }
  if (scene.statics.solver == "iterative")
    throw InputError("Static/Linear solver", "'iterative' is for solid scenes; an arm's factor is small and exact: "
                                             "allowed here: 'direct'");
  if (model->constraints().n_constraints() == 0)
    throw InputError("Arm/Supports", "the arm has no support: it moves freely under a static load; clamp or pin it");
  std::ostringstream d;
  d << "arm: " << arm.curve->description() << ", L = " << arm.curve->length() << " m, " << model->n_cells()
    << " elements of degree " << arm.degree;
  report.description = d.str();
  report.csv_header = "load_case,s_m,x_m,y_m,z_m,ux_m,uy_m,uz_m,theta_x_rad,theta_y_rad,theta_z_rad";
  for (const double s : points)
    {
      std::ostringstream label, fields;
      label << "s = " << std::setprecision(8) << s << " m";
      const auto x = arm.curve->position(s);
      fields << io::csv_number(s) << "," << io::csv_number(x[0]) << "," << io::csv_number(x[1]) << ","
             << io::csv_number(x[2]);
      report.labels.push_back(label.str());
      report.csv_fields.push_back(fields.str());
    }
  std::vector<Vector<double>> loads;
  const auto solutions = solve_cases(*model, scene, report, timer, loads);
  for (std::size_t i = 0; i < solutions.size(); ++i)
    {
      auto &r = report.cases[i];
      for (const double s : points)
        {
          const auto u = model->displacement_at(s, solutions[i].u), theta = model->rotation_at(s, solutions[i].u);
          r.values.push_back({u[0], u[1], u[2], theta[0], theta[1], theta[2]});
        }
      r.applied = scene.load_cases[i].resultant_on(arm);
      r.reactions = model->vertex_resultant(solutions[i].reaction);
    }
  const unsigned int subdivisions = scene.output.subdivisions;
  report.write_fields = [meshed, model, solutions, names = case_names(scene), subdivisions](io::OutputFolder &out) {
    out.add_text("section_forces.csv", section_force_table(*model, names, solutions));
    io::write_static_fields(out, *model, names, displacements(solutions), subdivisions);
  };
  report.files = ", section_forces.csv, static.pvd";
  return report;
}

/// Solids up to this many dofs take their residuals from the cell-by-cell internal forces (one
/// assembly per refinement step, about 0.1 s at this size); larger ones from the assembled K.
constexpr unsigned int exact_equilibrium_dofs = 50000;

Report solid_statics(const io::ArmScene &scene, TimerOutput &timer)
{
  Report report;
  std::shared_ptr<const fem::SolidModel> model;
  {
    TimerOutput::Scope t(timer, "assemble K");
    model = std::make_shared<const fem::SolidModel>(scene.solid, 0, false, false); // no mass: statics
  }
  if (model->constraints().n_constraints() == 0)
    throw InputError("Solid/Supports", "the solid has no support: it moves freely under a static load; fix a node "
                                       "set or a plane");
  report.description = "solid: " + scene.solid.mesh->source + ", " + std::to_string(model->n_cells()) + " cells";
  report.csv_header = "load_case,node_set,mean_ux_m,mean_uy_m,mean_uz_m,theta_x_rad,theta_y_rad,theta_z_rad";
  std::vector<std::string> sets = scene.statics.node_sets;
  if (sets.empty())
    for (const auto &c : scene.load_cases)
      {
        for (const auto &f : c.node_set_forces)
          if (std::find(sets.begin(), sets.end(), f.node_set) == sets.end()) sets.push_back(f.node_set);
        for (const auto &m : c.node_set_moments)
          if (std::find(sets.begin(), sets.end(), m.node_set) == sets.end()) sets.push_back(m.node_set);
        for (const auto &p : c.pressures)
          if (std::find(sets.begin(), sets.end(), p.node_set) == sets.end()) sets.push_back(p.node_set);
        for (const auto &n : c.node_forces)
          if (std::find(sets.begin(), sets.end(), n.node_set) == sets.end()) sets.push_back(n.node_set);
      }
  for (const auto &set : sets)
    {
      report.labels.push_back("node set " + set + " (mean u, best-fit rotation)");
      report.csv_fields.push_back(set);
    }
  reduction::StaticSolverSettings settings;
  settings.iterative = scene.statics.solver == "iterative" ||
                      (scene.statics.solver == "auto" && model->n_dofs() > fem::StaticSettings::iterative_above_dofs);
  settings.tolerance = scene.statics.tolerance;
  if (settings.iterative)
    settings.rigid_modes = model->rigid_body_modes();
  else if (model->n_dofs() <= exact_equilibrium_dofs)
    // Residuals from the cell-by-cell internal forces: reactions balance the loads to round-off
    // (reduction/static_solver.h); each refinement step then costs one assembly.
    settings.internal_forces = [model](const std::vector<long double> &u) { return model->internal_forces(u); };
  std::vector<Vector<double>> loads;
  const auto solutions = solve_cases(*model, scene, report, timer, loads, std::move(settings));
  for (std::size_t i = 0; i < solutions.size(); ++i)
    {
      auto &r = report.cases[i];
      for (const auto &set : sets)
        {
          const auto u = model->mean_displacement(set, solutions[i].u);
          const auto theta = fem::mean_rotation(*model, scene.solid, set, solutions[i].u);
          r.values.push_back({u[0], u[1], u[2], theta[0], theta[1], theta[2]});
        }
      // Isoparametric elements: the nodal load vector has the resultant of the loads it stands for.
      r.applied = model->nodal_resultant(loads[i]);
      r.reactions = model->nodal_resultant(solutions[i].reaction);
    }
  const unsigned int subdivisions = std::min(scene.output.subdivisions, 2u);
  report.write_fields = [model, solutions, material = scene.solid.material, names = case_names(scene),
                         subdivisions](io::OutputFolder &out) {
    io::write_static_fields(out, *model, material, names, displacements(solutions), subdivisions);
  };
  report.files = ", static.pvd";
  return report;
}

/// A body scene with its load cases: read here (io/body_scene.h declares no load cases) with
/// the body's own declarations plus "Static" and every "Load case NAME".
struct BodyStaticScene
{
  fem::Body body;
  reduction::ReductionSettings reduction;
  io::OutputSettings output;
  fem::StaticSettings statics;
  std::vector<fem::LoadCase> load_cases;
};

BodyStaticScene read_body_static_scene(const io::SceneFile &file, ParameterHandler &prm)
{
  BodyStaticScene scene;
  io::declare_body_scene(prm, fem::Body::parse_arm_list(*file.lists));
  fem::StaticSettings::declare_parameters(prm);
  fem::LoadCase::declare_parameters(prm, fem::StaticSettings::parse_load_case_list(*file.lists));
  file.parse(prm, false);
  scene.body = fem::Body::parse_parameters(prm, file.directory, file.has_subsection("Solid"));
  scene.reduction = reduction::ReductionSettings::parse_parameters(prm);
  scene.output = io::OutputSettings::parse_parameters(prm);
  scene.statics = fem::StaticSettings::parse_parameters(prm, nullptr, nullptr, &scene.body);
  if (scene.statics.solver == "iterative")
    throw InputError("Static/Linear solver", "'iterative' is for solid scenes; a body is solved twice with one "
                                             "factor each: allowed here: 'direct'");
  for (const auto &name : scene.statics.load_cases)
    scene.load_cases.push_back(fem::LoadCase::parse_parameters(prm, name, nullptr, nullptr, &scene.body));
  if (scene.load_cases.empty())
    throw InputError("Static/Load cases", "the scene has no load case; list them here and describe each in "
                                          "'subsection Load case NAME'");
  return scene;
}

std::string place_text(const reduction::PlaceValues &v)
{
  std::ostringstream o;
  o << std::setprecision(10) << "u = (" << v[0] << ", " << v[1] << ", " << v[2] << ") m, theta = (" << v[3] << ", "
    << v[4] << ", " << v[5] << ") rad";
  return o.str();
}

void print_body_case(const reduction::BodyStaticCase &r, const std::vector<fem::LoadPoint> &places)
{
  std::cout << "\n  load case " << r.name << "\n";
  for (std::size_t k = 0; k < places.size(); ++k)
    std::cout << "    " << places[k].label << ":\n      full:     " << place_text(r.full[k])
              << "\n      reduced:  " << place_text(r.reduced[k]) << "\n" << std::scientific << std::setprecision(2)
              << "      reduced against full: |u_r - u| / |u| = " << r.displacement_difference(k)
              << ",  |theta_r - theta| / |theta| = " << r.rotation_difference(k) << "\n"
              << std::defaultfloat;
  std::cout << std::setprecision(10) << "    strain energy:  full " << r.strain_energy_full << " J, reduced "
            << r.strain_energy_reduced << " J;" << std::scientific << std::setprecision(2)
            << "  relative residual of K u = f " << r.residual << "\n"
            << std::defaultfloat;
}

std::string body_csv(const std::vector<reduction::BodyStaticCase> &cases, const std::vector<fem::LoadPoint> &places)
{
  std::ostringstream csv;
  csv << "load_case,place,ux_m,uy_m,uz_m,theta_x_rad,theta_y_rad,theta_z_rad,reduced_ux_m,reduced_uy_m,reduced_uz_m,"
         "reduced_theta_x_rad,reduced_theta_y_rad,reduced_theta_z_rad,displacement_difference,rotation_difference\n";
  for (const auto &r : cases)
    for (std::size_t k = 0; k < places.size(); ++k)
      {
        csv << r.name << "," << places[k].label;
        for (const double v : r.full[k]) csv << "," << io::csv_number(v);
        for (const double v : r.reduced[k]) csv << "," << io::csv_number(v);
        csv << "," << io::csv_number(r.displacement_difference(k)) << "," << io::csv_number(r.rotation_difference(k))
            << "\n";
      }
  return csv.str();
}

std::string body_cases_json(const std::vector<reduction::BodyStaticCase> &cases,
                            const std::vector<fem::LoadPoint> &places)
{
  std::string list = "[";
  for (std::size_t i = 0; i < cases.size(); ++i)
    {
      const auto &r = cases[i];
      std::string at = "[";
      for (std::size_t k = 0; k < places.size(); ++k)
        {
          io::JsonObject p;
          p.add("at", places[k].label)
            .add("full", std::vector<double>(r.full[k].begin(), r.full[k].end()))
            .add("reduced", std::vector<double>(r.reduced[k].begin(), r.reduced[k].end()))
            .add("displacement_difference", r.displacement_difference(k))
            .add("rotation_difference", r.rotation_difference(k));
          at += (k ? ", " : "") + p.str(6);
        }
      io::JsonObject c;
      c.add("name", r.name)
        .raw("points", at + "]")
        .add("strain_energy_full_J", r.strain_energy_full)
        .add("strain_energy_reduced_J", r.strain_energy_reduced)
        .add("relative_residual", r.residual);
      list += (i ? ", " : "") + c.str(4);
    }
  return list + "]";
}

int body_static_command(const Options &options, const io::SceneFile &file, CommandClock &clock)
{
  auto &timer = clock.timer;
  ParameterHandler prm;
  BodyStaticScene scene;
  std::unique_ptr<fem::BodyModel> model;
  reduction::ReducedBasis basis;
  std::vector<fem::LoadPoint> places;
  std::vector<reduction::BodyStaticCase> cases;
  try
    {
      {
        TimerOutput::Scope t(timer, "read parameters and geometry");
        scene = read_body_static_scene(file, prm);
      }
      {
        TimerOutput::Scope t(timer, "assemble K");
        model = std::make_unique<fem::BodyModel>(scene.body);
      }
      std::cout << "flextrack static: " << file.name << "\n  body: " << model->n_dofs() << " body dofs ("
                << model->n_full_dofs() << " before ties and supports), " << scene.load_cases.size() << " load case"
                << (scene.load_cases.size() == 1 ? "" : "s") << "; reduced by " << scene.reduction.method_name()
                << std::endl;
      basis = reduction::reduce(*model, scene.reduction, &timer);
      std::cout << "  reduced body: " << basis.modes.size() << " modes (" << basis.n_normal << " normal, "
                << basis.n_interface << " interface, " << basis.n_track << " track load)" << std::endl;
      places = scene.statics.body_points.empty() ? reduction::default_body_places(scene.body, scene.load_cases)
                                                 : scene.statics.body_points;
      TimerOutput::Scope t(timer, "factorise and solve");
      const reduction::BodyStatics statics(*model, basis, scene.reduction);
      cases = statics.solve(scene.load_cases, places);
    }
  catch (const InputError &e)
    {
      throw e.file().empty() ? e.in_file(file.name) : e;
    }
  for (const auto &r : cases) print_body_case(r, places);

  io::OutputFolder out(io::OutputFolder::choose(options.output_directory, scene.output.directory, options.file));
  {
    TimerOutput::Scope t(timer, "write output");
    out.add_text("static.csv", body_csv(cases, places));
    out.add_parameters(prm);
    io::JsonObject summary;
    summary.add("program", "flextrack " FLEXTRACK_VERSION)
      .add("command", "static")
      .add("parameter_file", options.file)
      .add("set_on_command_line", io::override_texts(options.overrides))
      .add("model", "body")
      .add("body_degrees_of_freedom", model->n_dofs())
      .add("reduction_method", scene.reduction.method_name())
      .add("reduced_modes", static_cast<unsigned int>(basis.modes.size()))
      .raw("load_cases", body_cases_json(cases, places))
      .add("wall_time_s", io::timings_json(timer))
      .add("total_wall_time_s", clock.total_for_summary())
      .add("peak_memory_MiB", io::peak_memory_mib())
      .raw("parameters", io::parameters_as_json(prm));
    out.add_summary(summary);
  }
  out.commit();
  std::cout << "\n";
  print_timings(clock);
  std::cout << "  results in " << out.path() << "/ (static.csv, summary.json)" << std::endl;
  return 0;
}
} // namespace

int static_command(const Options &options, const io::SceneFile &file)
{
  CommandClock clock;
  auto &timer = clock.timer;
  if (Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
    throw InputError("", "'flextrack static' runs on one process; start it without mpirun", file.name);
  if (file.model == "body") return body_static_command(options, file, clock);
  ParameterHandler prm;
  io::ArmScene scene;
  {
    TimerOutput::Scope t(timer, "read parameters and geometry");
    if (file.model != "arm" && file.model != "solid")
      throw InputError("Model", "'flextrack static' solves arm, solid and body scenes ('Model = arm', 'solid' or "
                                "'body'); this scene is '" + file.model + "'", file.name);
    io::declare_arm_scene(prm);
    scene = io::read_arm_scene(file, prm);
    if (scene.load_cases.empty())
      throw InputError("Static/Load cases", "the scene has no load case; list them here and describe each in "
                                            "'subsection Load case NAME'", file.name);
  }
  Report report;
  try
    {
      report = scene.is_solid ? solid_statics(scene, timer) : arm_statics(scene, timer);
    }
  catch (const InputError &e)
    {
      throw e.file().empty() ? e.in_file(file.name) : e;
    }
  for (const auto &r : report.cases) print_case(r, report);

  io::OutputFolder out(io::OutputFolder::choose(options.output_directory, scene.output.directory, options.file));
  {
    TimerOutput::Scope t(timer, "write output");
    out.add_text("static.csv", csv_table(report));
    io::remove_static_fields(out.path());
    report.write_fields(out);
    out.add_parameters(prm);
    io::JsonObject summary;
    summary.add("program", "flextrack " FLEXTRACK_VERSION)
      .add("command", "static")
      .add("parameter_file", options.file)
      .add("set_on_command_line", io::override_texts(options.overrides))
      .add("model", report.description)
      .add("elements", report.n_cells)
      .add("degrees_of_freedom", report.n_dofs)
      .add("free_degrees_of_freedom", report.n_free_dofs)
      .add("linear_solver", report.solver)
      .add("cg_iterations", report.cg_iterations)
      .raw("load_cases", cases_json(report))
      .add("wall_time_s", io::timings_json(timer))
      .add("total_wall_time_s", clock.total_for_summary())
      .add("peak_memory_MiB", io::peak_memory_mib())
      .raw("parameters", io::parameters_as_json(prm));
    out.add_summary(summary);
  }
  out.commit();
  std::cout << "\n";
  print_timings(clock);
  std::cout << "  results in " << out.path() << "/ (static.csv, summary.json" << report.files << ")" << std::endl;
  return 0;
}
} // namespace flextrack::app
