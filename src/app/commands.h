// The commands of the flextrack program, one function each; main.cc holds the table that maps
// a command name to its function. Each returns the process exit code.
#pragma once

#include <io/scene_file.h>

#include <deal.II/base/timer.h>

#include <sstream>
#include <string>

namespace flextrack::app
{
struct Options
{
  std::string file;
  std::string output_directory; ///< from -o; empty = from the file, else output/<stem>
  unsigned int refinements = 3; ///< converge: number of refinements K
  std::string format;           ///< export: a name of io::export_formats()
  std::string mbdyn_clamp;      ///< export: --mbdyn-clamp (auto, yes, no); empty = not given
  std::vector<io::ParameterOverride> overrides; ///< --set ENTRY=VALUE, in their order
  unsigned int jobs = 0;        ///< sweep: -j N, cases run at once on this machine; 0: not given
};

/// Time simulation of a multibody scene (Model = multibody): probes.csv, monitors.csv,
/// results.h5, summary.json, parameters_used.prm. Needs no MPI unless a body must be reduced.
int run_command(const Options &options, const io::SceneFile &file);
/// Work-precision of the integrators on a multibody scene: bench.csv, bench.png, summary.json.
int bench_command(const Options &options, const io::SceneFile &file);
/// A parameter study of a multibody scene ("Model = study", doc/sweep.md): every case run in
/// OUT/case_NNNN/, sweep.csv and sweep.png; `-j N` cases at once, or shared out over mpirun's
/// processes; a rerun runs only the cases not yet finished.
int sweep_command(const Options &options, const io::SceneFile &file);
/// Frequencies and damping ratios of a multibody scene linearised about its initial state.
int linearize_command(const Options &options, const io::SceneFile &file);
/// The parameters of a multibody scene (one body, joint, force and probe called NAME).
void print_multibody_parameters();
/// Starts MPI (once) for a command that did not need it until now: a run whose flexible body
/// must be reduced (the FE stage distributes its matrices). A no-op if MPI runs already.
void start_mpi_for_reduction();
/// Natural modes of one arm or solid (a body scene is reduced instead): frequencies.csv,
/// summary.json, mode shapes (VTU/PVD).
int modes_command(const Options &options, const io::SceneFile &file);
/// The same analysis on K successively halved meshes: convergence.csv, convergence.png.
int converge_command(const Options &options, const io::SceneFile &file);
/// Reduce the flexible body of a "Model = body" scene: reduced_body.h5 (cached), frequencies.csv,
/// summary.json, and the exports of Output/Export formats.
int reduce_command(const Options &options, const io::SceneFile &file);
/// Linear statics of an arm or solid scene under its load cases (Static/Load cases): displacements and
/// rotations at the report points, reactions against the applied loads, strain energy;
/// static.csv, summary.json, parameters_used.prm.
int static_command(const Options &options, const io::SceneFile &file);
/// Export a reduced body file for another tool (--format).
int export_command(const Options &options);
/// Print what a reduced body file holds (checks it thoroughly).
int inspect_command(const Options &options);
/// Every parameter with its default, allowed values, unit and documentation.
int print_parameters_command();

/// The wall clock of a command and the timer of its stages (summarised at the end).
struct CommandClock
{
  dealii::Timer wall;
  std::ostringstream log;
  dealii::TimerOutput timer{log, dealii::TimerOutput::never, dealii::TimerOutput::wall_times};
  /// The total wall time for summary.json, taken once: the log then prints the same number and
  /// what came after it (issue 25, item 12: the log said 3.56 s, summary.json 3.317 s).
  double summary_total = -1;
  double total_for_summary()
  {
    summary_total = wall.wall_time();
    return summary_total;
  }
};

/// "  wall time [s]:  stage t; ...  total T" and the peak memory, on stdout; stages may nest (a
/// body's reduction within the scene's reading), so they need not add up to the total.
void print_timings(const CommandClock &clock);
} // namespace flextrack::app
