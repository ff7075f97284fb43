// Everything FlexTrack hands to gnuplot, in one place (issue 23, item 1).
//  - gnuplot_string(): the one quoting function for text from input (a scene's path, a title,
//    probe and body names) that goes into a gnuplot script. Every script below takes its text
//    through it; nothing else writes text into a .gp file.
//  - The scripts FlexTrack writes: convergence.gp (converge), bench.gp (bench), deviation.gp
//    (run with a rigid reference), run.gp (every run). Each is a pure function of its fields, so a test can feed
//    hostile text through every field of every script (tests/unit/gnuplot_test.cc).
//  - draw_png(): runs gnuplot on a script in the output folder (argument vector, no shell) with
//    the PNG written under a temporary name, checked to be a complete PNG (a full disk leaves a
//    truncated one and gnuplot still exits 0), then renamed: a PNG in the folder is whole.
//    A script written here names its PNG through the variable png_file, which draw_png sets and
//    which defaults to the final name when a user runs `gnuplot NAME.gp` by hand.
#pragma once

#include <string>
#include <vector>

namespace flextrack::io
{
/// @p text as a gnuplot string expression: single-quoted literals, inside which gnuplot interprets
/// nothing (no backslash escapes, no macro or backquote substitution), joined by the string "'"
/// where the text has a quote ('it'."'".'s'). Control characters (a newline would end the command and
/// let the next line start with '!' or 'system') and DEL become a blank. The text is otherwise
/// kept, so a title shows the file name the user typed.
std::string gnuplot_string(const std::string &text);

/// convergence.gp: relative error of each of @p n_modes frequencies against the finest level
/// versus dofs (from convergence.csv), titled @p title.
std::string convergence_plot_script(const std::string &title, unsigned int n_modes);

/// bench.gp: largest relative probe error against integration wall time, one line per method
/// (from bench.csv, whose wall time is column 6 + @p n_probes), titled @p title.
std::string bench_plot_script(const std::string &title, unsigned int n_probes);

/// deviation.gp: the paths of the run and of its rigid reference in the x-y plane and the
/// deviation against time, one line per probe of @p probe_names (probes.csv, deviation.csv).
std::string deviation_plot_script(const std::vector<std::string> &probe_names);

/// run.gp: the run at a glance, from probes.csv (if @p probe_names is not empty) and
/// monitors.csv: the probes' x, y, z against time; kinetic, gravity and strain energy and the
/// work of drivers and loads; the energy balance error; the constraint residuals (log scales,
/// values below 1e-16 drawn at 1e-16). Titled @p title (the scene).
std::string run_plot_script(const std::string &title, const std::vector<std::string> &probe_names);

/// sweep.gp: from sweep.csv (case, the parameters, the quantities), the first four quantities
/// against the one parameter of @p parameters, one panel each; or, over two parameters, the
/// first quantity as the colour of a map. Titled @p title.
std::string sweep_plot_script(const std::string &title, const std::vector<std::string> &parameters,
                              const std::vector<std::string> &quantities);

/// The outcome of draw_png: drawn, or why not (gnuplot missing, failed, the PNG incomplete).
struct PlotResult
{
  bool drawn = false;
  std::string problem; ///< empty when drawn
};

/// Runs `gnuplot SCRIPT` in @p folder with png_file set to a temporary name, checks that the
/// temporary is a complete PNG and renames it to @p png. On failure removes the temporary and
/// leaves no @p png (an older one is removed too: it would belong to another run).
PlotResult draw_png(const std::string &folder, const std::string &script, const std::string &png);
} // namespace flextrack::io
