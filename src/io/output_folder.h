// The one output rule of every command.
//  - The folder is -o, else the scene's Output/Directory, else output/<parameter file stem>.
//  - Every file is written under a temporary name (NAME.writing-PID) and renamed to NAME only
//    when the whole run has succeeded (commit()): a failed run leaves no new, half-written or
//    mixed results; the temporaries are removed when the folder object is destroyed uncommitted.
//  - A write error (a full disk, a read-only folder) is an InputError that says which file and
//    why, never an internal error.
//  - Under MPI only the first process writes text files (every process computes them alike).
// The standard files (frequencies.csv, parameters_used.prm, summary.json) are written here only.
#pragma once

#include <io/json.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <functional>
#include <string>
#include <vector>

namespace flextrack::io
{
/// Writes @p path atomically: @p write fills a temporary PATH.writing-PID in the same folder,
/// renamed to PATH when @p write returns, removed when it throws. InputError if it fails.
void write_atomically(const std::string &path, const std::function<void(const std::string &temporary)> &write);

/// True on the first MPI process, and in a program that has not started MPI.
bool is_first_process();

class OutputFolder
{
public:
  /// The folder of a run (see above).
  static std::string choose(const std::string &option, const std::string &scene_directory, const std::string &file);
  /// The folder @p path, created (with its parents) when the first file is added: a run that
  /// fails before it has results leaves no folder behind. InputError if it cannot be created.
  explicit OutputFolder(std::string path);
  /// Creates the folder now (also done by the first add_text / add_file).
  void create() const;
  ~OutputFolder();
  OutputFolder(const OutputFolder &) = delete;
  OutputFolder &operator=(const OutputFolder &) = delete;

  const std::string &path() const { return folder; }
  /// Writes @p text to a temporary for file @p name (first process only).
  void add_text(const std::string &name, const std::string &text);
  /// A temporary path for file @p name that a writer fills itself (HDF5, VTU); renamed at commit.
  std::string add_file(const std::string &name);
  /// Tidies up after the previous run of @p command in this folder: commit() then removes the
  /// files that run wrote (listed in the folder's manifest .flextrack_COMMAND_files) and this one
  /// did not (an animation.pvd, a deviation.csv of a run whose scene has changed), and lists this
  /// run's files there. Only files a manifest lists are ever removed; other commands' files and a
  /// user's own are kept.
  void tidy_previous_run(const std::string &command);
  /// A file a program adds to the folder after commit() (gnuplot's PNG): listed in the manifest.
  void will_add(const std::string &name);
  /// Renames every added file to its name; returns the names (then the manifest, above).
  std::vector<std::string> commit();

  /// frequencies.csv: mode, frequency [Hz].
  void add_frequencies(const std::vector<double> &frequencies_hz);
  /// parameters_used.prm: every parameter of the run, to reproduce it.
  void add_parameters(const dealii::ParameterHandler &prm);
  /// summary.json.
  void add_summary(const JsonObject &summary);

private:
  std::string folder;
  std::vector<std::pair<std::string, std::string>> staged; // temporary, final
  std::vector<std::string> announced;                      // will_add()
  std::string manifest;                                    // tidy_previous_run(): its name in the folder
  bool committed = false;
  void replace_manifest(const std::vector<std::string> &written) const;
};

/// Every parameter as JSON (short form), for summary.json.
std::string parameters_as_json(const dealii::ParameterHandler &prm);
/// Wall time per timer section as a JSON object [s].
JsonObject timings_json(const dealii::TimerOutput &timer);
/// Peak resident memory of this process so far [MiB].
double peak_memory_mib();
/// A number with 12 significant digits for CSV files.
std::string csv_number(double v);
} // namespace flextrack::io
