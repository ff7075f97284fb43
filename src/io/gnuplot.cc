#include <io/gnuplot.h>

#include <base/external_program.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

namespace flextrack::io
{
std::string gnuplot_string(const std::string &text)
{
  // gnuplot's own escape of a quote inside single quotes ('') is ambiguous where the text starts
  // with a quote: in a plot title ''' reads as an empty string and a stray quote, and the plot
  // fails. So no quote is ever written inside a literal: the text is cut at each quote and the
  // pieces are joined by the string "'" ('it'."'".'s'). A double-quoted string that holds only a
  // quote has nothing for gnuplot to interpret (no backslash, no backquote).
  std::string quoted = "'";
  for (const char c : text)
    {
      const auto byte = static_cast<unsigned char>(c);
      if (byte < 0x20 || byte == 0x7f)
        quoted += ' ';
      else if (c == '\'')
        quoted += "'.\"'\".'";
      else
        quoted += c;
    }
  return quoted + "'";
}

namespace
{
/// The first lines of every script: a PNG terminal and the output file png_file (set by
/// draw_png to a temporary name; the final name when a user runs the script by hand).
std::string png_preamble(const std::string &png, const std::string &size)
{
  return "set terminal pngcairo size " + size + " noenhanced\n" + "if (!exists('png_file')) png_file = " +
         gnuplot_string(png) + "\nset output png_file\n";
}
} // namespace

std::string convergence_plot_script(const std::string &title, const unsigned int n_modes)
{
  std::ostringstream gp;
  gp << "# gnuplot script written by flextrack converge: convergence.png\n"
     << png_preamble("convergence.png", "900,650") << "set datafile separator ','\nset logscale xy\nset grid\n"
     << "set key outside right\nset xlabel 'degrees of freedom'\n"
     << "set ylabel 'relative frequency error vs finest level'\n"
     << "set title " << gnuplot_string(title) << "\n"
     << "plot for [m=1:" << n_modes << "] 'convergence.csv' using ($1==m && $8 > 0 ? $4 : NaN):8 "
     << "with linespoints title sprintf('mode %d', m)\n";
  return gp.str();
}

std::string bench_plot_script(const std::string &title, const unsigned int n_probes)
{
  const std::string wall = std::to_string(6 + n_probes);
  std::ostringstream gp;
  gp << "# gnuplot script written by flextrack bench: bench.png\n"
     << png_preamble("bench.png", "900,620") << "set datafile separator ','\nset logscale xy\n"
     << "set format y '%.0e'\nset grid\nset key top right\n"
     << "set xlabel 'integration wall time [s]'\nset ylabel 'largest relative probe error [-]'\n"
     << "set title " << gnuplot_string(title) << "\n"
     << "plot 'bench.csv' using ($5 > 0 && strcol(1) eq 'ida' ? $" << wall
     << " : 1/0):5 with linespoints pt 7 title 'IDA (BDF), rtol 1e-3 ... 1e-10', \\\n"
     << "     'bench.csv' using ($5 > 0 && strcol(1) eq 'radau' ? $" << wall
     << " : 1/0):5 with linespoints pt 9 title 'Radau IIA (order 5), rtol 1e-3 ... 1e-10', \\\n"
     << "     'bench.csv' using ($5 > 0 && strcol(1) eq 'generalized_alpha' ? $" << wall
     << " : 1/0):5 with linespoints pt 5 title 'generalised-alpha, fixed steps'\n";
  return gp.str();
}

std::string deviation_plot_script(const std::vector<std::string> &names)
{
  // Columns: probes.csv has time, then 6 per probe (x, y, z, vx, vy, vz); deviation.csv time,
  // then 4 per probe.
  std::ostringstream gp;
  gp << "# gnuplot script written by flextrack run (Multibody/Rigid reference): deviation.png\n"
     << png_preamble("deviation.png", "1200,520") << "set datafile separator ','\nset grid\nset key top left\n"
     << "set multiplot layout 1,2 title 'Probe paths: the run and its rigid reference (every body rigid)'\n"
     << "set title 'path, x-y projection'\nset xlabel 'x [m]'\nset ylabel 'y [m]'\nset size ratio -1\nplot ";
  for (std::size_t p = 0; p < names.size(); ++p)
    gp << (p ? ", " : "") << "'probes.csv' using " << 2 + 6 * p << ":" << 3 + 6 * p << " with lines lw 2 title "
       << gnuplot_string(names[p]) << ", 'deviation.csv' using " << 2 + 4 * p << ":" << 3 + 4 * p
       << " with lines dt 2 lw 2 title " << gnuplot_string(names[p] + ", rigid");
  gp << "\nset size noratio\nset title 'deviation from the rigid path'\nset xlabel 'time [s]'\n"
     << "set ylabel '|r - r_rigid| [mm]'\nplot ";
  for (std::size_t p = 0; p < names.size(); ++p)
    gp << (p ? ", " : "") << "'deviation.csv' using 1:($" << 5 + 4 * p << "*1000) with lines lw 2 title "
       << gnuplot_string(names[p]);
  gp << "\nunset multiplot\n";
  return gp.str();
}

std::string run_plot_script(const std::string &title, const std::vector<std::string> &names)
{
  // Columns: probes.csv time, then 6 per probe (x, y, z, vx, vy, vz); monitors.csv (io/run_results.cc)
  // 1 time, 2 position residual, 3 velocity residual, 4 ||p|-1|, 5 kinetic, 6 gravity, 7 strain,
  // 8 spring energy, 9 work of applied loads, 10 work of drivers, 11 dissipated, 12 balance error.
  std::ostringstream gp;
  gp << "# gnuplot script written by flextrack run: run.png (Output/Plots)\n"
     << png_preamble("run.png", "1200,900") << "set datafile separator ','\nset grid\nset key top left opaque\n"
     << "on_log(x) = abs(x) > 1e-16 ? abs(x) : 1e-16\n"
     << "set multiplot layout 2,2 title " << gnuplot_string(title) << "\nset xlabel 'time [s]'\n";
  if (names.empty())
    gp << "set title 'no probes (Multibody/Probes)'\nunset key\nplot 'monitors.csv' using 1:(0) with lines lt 0 "
          "notitle\nset key top left\n";
  else
    {
      gp << "set title 'probes'\nset ylabel 'coordinate [m]'\nplot ";
      const char *axis[3] = {"x", "y", "z"};
      for (std::size_t p = 0; p < names.size(); ++p)
        for (unsigned int d = 0; d < 3; ++d)
          gp << (p + d ? ", " : "") << "'probes.csv' using 1:" << 2 + 6 * p + d << " with lines lw 2 title "
             << gnuplot_string(names[p] + " " + axis[d]);
      gp << "\n";
    }
  gp << "set title 'energy'\nset ylabel 'energy, work [J]'\nplot 'monitors.csv' using 1:5 with lines lw 2 title "
        "'kinetic', '' using 1:6 with lines lw 2 title 'gravity', '' using 1:7 with lines lw 2 title 'strain', '' "
        "using 1:8 with lines lw 2 title 'springs', '' "
        "using 1:($9+$10) with lines lw 2 title 'work of loads and drivers', '' using 1:11 with lines lw 2 title "
        "'dissipated'\n"
     << "set logscale y\nset format y '%.0e'\nset title 'energy balance error (of the energy scale)'\n"
        "set ylabel 'error [-]'\nplot 'monitors.csv' using 1:(on_log($12)) with lines lw 2 notitle\n"
     << "set title 'constraint residuals'\nset ylabel 'residual [m, m/s, -]'\nplot 'monitors.csv' using "
        "1:(on_log($2)) with lines lw 2 title '|Phi| [m or rad]', '' using 1:(on_log($3)) with lines lw 2 title "
        "'|dPhi/dt| [m/s or rad/s]', '' using 1:(on_log($4)) with lines lw 2 title '||p| - 1| [-]'\n"
     << "unset multiplot\n";
  return gp.str();
}

std::string sweep_plot_script(const std::string &title, const std::vector<std::string> &parameters,
                              const std::vector<std::string> &quantities)
{
  // Columns of sweep.csv: 1 case, 2 ... 1 + P the parameters, then the quantities, then status.
  // A case that did not complete has no quantities: it is marked with a red cross (on the x
  // axis of each panel, or at its place on the map), so that a gap in a curve is explained.
  const std::size_t first = 2 + parameters.size(), status = first + quantities.size();
  const std::string not_completed = "(strcol(" + std::to_string(status) + ") eq 'completed' ? NaN : ";
  std::ostringstream gp;
  gp << "# gnuplot script written by flextrack sweep: sweep.png\n";
  if (parameters.size() == 1)
    {
      const std::size_t panels = std::min<std::size_t>(4, quantities.size());
      gp << png_preamble("sweep.png", "900," + std::to_string(120 + 260 * panels))
         << "set datafile separator ','\nset grid\nset key top right\nset y2range [0:1]\nunset y2tics\n"
         << "set multiplot layout " << panels << ",1 title " << gnuplot_string(title) << "\n"
         << "set xlabel " << gnuplot_string(parameters[0]) << "\n";
      for (std::size_t k = 0; k < panels; ++k)
        gp << "set ylabel " << gnuplot_string(quantities[k]) << "\nplot 'sweep.csv' using 2:" << first + k
           << " with linespoints pt 7 lw 2 notitle, '' using 2:" << not_completed
           << "0.03) axes x1y2 with points pt 2 ps 2 lw 2 lc 'red' title 'case not completed'\n";
      gp << "unset multiplot\n";
    }
  else
    gp << png_preamble("sweep.png", "900,700") << "set datafile separator ','\nset grid\nset key below\n"
       << "set title " << gnuplot_string(title + ": " + quantities.at(0)) << "\n"
       << "set xlabel " << gnuplot_string(parameters[0]) << "\nset ylabel " << gnuplot_string(parameters[1]) << "\n"
       << "set cblabel " << gnuplot_string(quantities[0]) << "\nset palette rgbformulae 33,13,10\nset offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05\n"
       << "set format cb '%.4g'\nset rmargin at screen 0.8\n"
       << "plot 'sweep.csv' using 2:3:" << first << " with points pt 5 ps 5 palette notitle, '' using 2:3:(strcol(" << status
       << ") eq 'completed' ? sprintf('%.4g', column(" << first << ")) : strcol(" << status
       << ")) with labels offset 0,1.6 font ',9' notitle, '' using 2:" << not_completed
       << "$3) with points pt 2 ps 4 lw 3 lc 'black' title 'case not completed'\n";
  return gp.str();
}

namespace
{
/// True if @p path holds a whole PNG: its signature first and its IEND chunk last (a write cut
/// short by a full disk keeps the first and loses the second).
bool is_complete_png(const std::string &path)
{
  std::ifstream f(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  static const std::string signature("\x89PNG\r\n\x1a\n", 8);
  static const std::string trailer("\0\0\0\0IEND\xae\x42\x60\x82", 12);
  return bytes.size() >= signature.size() + trailer.size() && bytes.compare(0, signature.size(), signature) == 0 &&
         bytes.compare(bytes.size() - trailer.size(), trailer.size(), trailer) == 0;
}
} // namespace

PlotResult draw_png(const std::string &folder, const std::string &script, const std::string &png)
{
  const std::string temporary = png + ".writing-" + std::to_string(::getpid());
  const std::string folder_slash = folder.empty() ? std::string() : folder + "/";
  std::remove((folder_slash + png).c_str());
  // png_file is our own name (the PNG's fixed name and a number): quoted all the same.
  const int status = base::run_program({"gnuplot", "-e", "png_file = " + gnuplot_string(temporary), script},
                                       folder.empty() ? std::string(".") : folder);
  PlotResult result;
  if (status < 0)
    result.problem = "gnuplot is not installed";
  else if (status != 0)
    result.problem = "gnuplot failed (exit status " + std::to_string(status) + ")";
  else if (!is_complete_png(folder_slash + temporary))
    result.problem = "gnuplot's " + png + " is incomplete (is the disk full?)";
  else if (std::rename((folder_slash + temporary).c_str(), (folder_slash + png).c_str()) != 0)
    result.problem = "could not rename " + temporary + " to " + png;
  else
    result.drawn = true;
  if (!result.drawn) std::remove((folder_slash + temporary).c_str());
  return result;
}
} // namespace flextrack::io
