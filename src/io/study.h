// A parameter study ("set Model = study", run by `flextrack sweep`; doc/sweep.md): a multibody
// scene, the entries to vary and how (a list or range of values per parameter, combined as a
// grid or side by side, or a random / Latin-hypercube sample of intervals with a seed), the
// entries set in every case, and the quantities to collect from each case's results.
//
// A case is the scene with one `--set` per varied parameter (io/parameter_overrides.h), so a
// case is checked and run exactly as `flextrack run SCENE --set ...` would; its key (a hash of
// the scene's text and the case's entries) tells a finished case of the same study from a stale
// one when a study is run again.
//
// The study's parameters are named in `Study/Parameters` and each described in its own
// `subsection Parameter NAME` (the two-pass pattern of io/scene_file.h).
#pragma once

#include <io/parameter_overrides.h>
#include <io/scene_file.h>

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace flextrack::io
{
/// One varied entry.
struct StudyParameter
{
  std::string name;                ///< the NAME of `subsection Parameter NAME` (a column of sweep.csv)
  ParameterOverride entry;         ///< scope and path of the entry; value unused
  std::string value_template;      ///< the value set, with "{}" replaced by the case's value
  std::vector<std::string> values; ///< list and range designs
  double lower = 0, upper = 0;     ///< sampled designs: the interval
  bool integer = false;            ///< sampled designs: round to integers
};

/// What to collect from a case folder (a column of sweep.csv).
struct Quantity
{
  enum class Kind
  {
    summary,   ///< a value of summary.json, by its '/'-separated path ("integrator/steps")
    column,    ///< a statistic of a column of probes.csv, deviation.csv or monitors.csv
    reference  ///< largest distance of a probe from its position in the reference case
  };
  std::string text; ///< as written in Study/Collect (the column name)
  Kind kind = Kind::summary;
  std::string path;      ///< summary: the key path; column: the column name; reference: the probe
  std::string statistic; ///< column: max, min, max_abs, final, mean, time_of_max, time_of_min
};

struct StudyCase
{
  unsigned int number = 0;               ///< 1-based
  std::vector<std::string> values;       ///< one per parameter, as substituted
  std::vector<ParameterOverride> set;    ///< the study's fixed entries, then the varied ones
  std::string folder;                    ///< OUT/case_NNNN
  std::string key;                       ///< hash of the scene text and the entries set
};

struct Study
{
  std::string file;             ///< the study file (messages)
  std::string scene;            ///< the multibody scene, absolute path
  std::string output_directory; ///< Study/Output directory, else output/<study file stem>
  std::string design;           ///< grid, zip, random, latin hypercube
  unsigned int samples = 0, seed = 1;
  std::vector<StudyParameter> parameters;
  std::vector<ParameterOverride> fixed; ///< Study/Set: set in every case
  std::vector<Quantity> quantities;
  unsigned int reference_case = 0; ///< 1-based; 0: none (no 'difference(PROBE)' collected)

  /// Every case of the design, in order; their folders under @p output_folder.
  std::vector<StudyCase> cases(const std::string &scene_text, const std::string &output_folder) const;
};

/// Declares the entries of a study whose parameters are @p names.
void declare_study(dealii::ParameterHandler &prm, const std::vector<std::string> &names);
/// Pass 1: the list of parameter names (Study/Parameters).
void declare_study_parameter_list(dealii::ParameterHandler &prm);

/// Reads the study of @p file ("Model = study"); InputError naming the file and entry.
Study read_study(const SceneFile &file);

/// The collected values of @p quantities (not those of kind reference) from the results in
/// @p folder, as texts ("" where a value is missing: a failed run, a probe not in the scene).
std::vector<std::string> collect_quantities(const std::vector<Quantity> &quantities, const std::string &folder);

/// Largest distance over the output rows between probe @p probe in the probes.csv of @p folder
/// and in that of @p reference_folder, as text; "" if either is missing or their output times differ.
std::string probe_difference(const std::string &probe, const std::string &folder, const std::string &reference_folder);
} // namespace flextrack::io
