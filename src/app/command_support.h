// Small helpers shared by the commands: output folder, text files, timings, memory.
#pragma once

#include <io/json.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <string>

namespace flextrack::app
{
/// The output folder of a run: -o, else the scene's Output/Directory, else
/// output/<parameter file name without extension>.
std::string output_directory(const std::string &option, const std::string &scene_directory, const std::string &file);
/// Create @p dir (and parents); InputError if it cannot be created.
void make_directory(const std::string &dir);
/// Peak resident memory of this process so far [MiB].
double peak_memory_mib();
/// Every parameter as JSON (short form).
std::string parameters_as_json(const dealii::ParameterHandler &prm);
/// Under MPI, the first process writes the text results (every process computes them alike).
bool is_root();
/// Write @p text to @p path (first process only); InputError if it cannot be written.
void write_text(const std::string &path, const std::string &text);
/// Wall time per timer section as a JSON object [s].
io::JsonObject timings_json(const dealii::TimerOutput &timer);
/// A number with 12 significant digits for CSV files.
std::string csv_number(double v);
} // namespace flextrack::app
