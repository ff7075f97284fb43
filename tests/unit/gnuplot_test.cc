// Issue 23, item 1: no text from input can make gnuplot run a command. Every gnuplot script
// FlexTrack writes (io/gnuplot.h: convergence.gp, bench.gp, deviation.gp) is written with
// hostile text in each of its text fields and run by gnuplot through io::draw_png, as the commands
// run it; the test asserts that no command ran (no file PWNED appeared), that the PNG was drawn
// and is whole, and that the hostile text reached the script as one string literal.
// The hostile texts are the two injections reproduced against `bench` (a quote that ends the
// title and a newline followed by '!'), and the other ways into gnuplot's command line:
// backquote substitution, macros (@), system(), a backslash before the quote, a double quote.
#include <io/gnuplot.h>

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>

namespace
{
namespace fs = std::filesystem;
using flextrack::io::gnuplot_string;

const std::vector<std::string> &hostile_texts()
{
  static const std::vector<std::string> texts = {
    "x'; system 'touch PWNED'; y='.prm",
    "scene\n!touch PWNED\n.prm",
    "scene\r\n!touch PWNED",
    "`touch PWNED`",
    "'.`touch PWNED`.'",
    "x'; cmd = 'system(\"touch PWNED\")'; @cmd; y='",
    "@cmd",
    "\\'; system('touch PWNED'); x='\\",
    "\"; system(\"touch PWNED\"); x=\"",
    "'\nset output 'PWNED'\nplot x\n'",
    "''''",
    std::string("nul") + '\0' + "byte'; system 'touch PWNED'; x='",
  };
  return texts;
}

/// A fresh folder with the data files the scripts read (a few rows each, in the commands' layout).
fs::path data_folder(const std::string &name)
{
  const fs::path folder = fs::temp_directory_path() / ("flextrack_gnuplot_" + std::to_string(::getpid())) / name;
  fs::remove_all(folder);
  fs::create_directories(folder);
  std::ofstream(folder / "convergence.csv")
    << "mode,level,elements,dofs,frequency_Hz,change,order,error,wall_time_s\n"
    << "1,0,4,30,10.5,,,0.01,0.1\n1,1,8,60,10.4,0.01,,0.001,0.1\n1,2,16,120,10.39,0.001,3.3,,0.1\n";
  std::ofstream(folder / "bench.csv") << "# header\nmethod,setting,value,status,max_relative_error,error_p_m,wall_time_s\n"
                                      << "ida,rtol 1e-03,0.001,completed,0.01,0.001,0.02\n"
                                      << "ida,rtol 1e-04,0.0001,completed,0.001,0.0001,0.03\n"
                                      << "generalized_alpha,step 0.01 s,0.01,completed,0.02,0.002,0.05\n"
                                      << "generalized_alpha,step 0.005 s,0.005,completed,0.005,0.0005,0.09\n";
  std::ofstream(folder / "probes.csv") << "time_s,a_x,a_y,a_z,a_vx,a_vy,a_vz\n0,1,0,0,0,1,0\n0.5,0.9,0.4,0,0,1,0\n1,0.5,0.8,0,0,1,0\n";
  std::ofstream(folder / "monitors.csv") << "time_s,pr,vr,nd,ke,ge,se,sp,wa,wd,di,eb\n"
                                         << "0,0,0,0,0,1,0,0,0,0,0,0\n0.5,1e-9,1e-7,1e-12,0.5,0.5,0,0,0,0,0,1e-8\n"
                                         << "1,2e-9,1e-6,0,0.1,0.9,0,0,0,0,0,2e-8\n";
  std::ofstream(folder / "deviation.csv") << "time_s,a_rigid_x_m,a_rigid_y_m,a_rigid_z_m,a_deviation_m\n"
                                          << "0,1,0,0,0\n0.5,0.9,0.41,0,0.001\n1,0.5,0.81,0,0.002\n";
  return folder;
}

/// Removes a folder from data_folder() and, once it is empty, the per-process parent holding it.
void remove_data_folder(const fs::path &folder)
{
  fs::remove_all(folder);
  std::error_code not_empty_yet;
  fs::remove(folder.parent_path(), not_empty_yet);
}

bool have_gnuplot()
{
  return std::system("gnuplot --version >/dev/null 2>&1") == 0;
}

/// Writes @p script into a fresh folder, draws it and checks that nothing ran and the PNG is there.
void expect_harmless(const std::string &case_name, const std::string &script_name, const std::string &script,
                     const std::string &png)
{
  const fs::path folder = data_folder(case_name);
  std::ofstream(folder / script_name) << script;
  const flextrack::io::PlotResult result = flextrack::io::draw_png(folder.string(), script_name, png);
  EXPECT_FALSE(fs::exists(folder / "PWNED")) << case_name << ": gnuplot ran a command; the script:\n" << script;
  EXPECT_TRUE(result.drawn) << case_name << ": " << result.problem << "; the script:\n" << script;
  EXPECT_TRUE(fs::exists(folder / png)) << case_name;
  for (const auto &entry : fs::directory_iterator(folder))
    EXPECT_EQ(entry.path().filename().string().find(".writing-"), std::string::npos)
      << case_name << ": temporary left: " << entry.path();
  remove_data_folder(folder);
}
} // namespace

// The expression is single-quoted literals joined by the string "'": inside a single-quoted
// literal gnuplot interprets nothing, and no quote is ever inside one (gnuplot 5.4 manual,
// "Quote Marks"); control characters become blanks.
TEST(Gnuplot, StringIsLiteralsJoinedByQuotes)
{
  EXPECT_EQ(gnuplot_string("plain"), "'plain'");
  EXPECT_EQ(gnuplot_string("it's"), "'it'.\"'\".'s'");
  EXPECT_EQ(gnuplot_string("'"), "''.\"'\".''");
  EXPECT_EQ(gnuplot_string("a\nb\rc\td\x7f"), "'a b c d '");
  EXPECT_EQ(gnuplot_string("`x` @y \\ \""), "'`x` @y \\ \"'");
  const std::string joint = ".\"'\".";
  for (const auto &text : hostile_texts())
    {
      // literal (joint literal)*, where a literal is a quote, anything but a quote or a control
      // character, a quote.
      const std::string e = gnuplot_string(text);
      std::size_t i = 0;
      for (;;)
        {
          ASSERT_LT(i, e.size()) << e;
          ASSERT_EQ(e[i], '\'') << e;
          const std::size_t close = e.find('\'', i + 1);
          ASSERT_NE(close, std::string::npos) << e;
          for (std::size_t k = i + 1; k < close; ++k) EXPECT_GE(static_cast<unsigned char>(e[k]), 0x20) << e;
          i = close + 1;
          if (i == e.size()) break;
          ASSERT_EQ(e.compare(i, joint.size(), joint), 0) << e;
          i += joint.size();
        }
    }
}

TEST(Gnuplot, EveryScriptWithHostileTextRunsNoCommand)
{
  ASSERT_TRUE(have_gnuplot()) << "gnuplot is a test dependency (.ci/setup installs gnuplot-nox)";
  unsigned int n = 0;
  for (const auto &text : hostile_texts())
    {
      const std::string tag = std::to_string(n++);
      expect_harmless("convergence_" + tag, "convergence.gp",
                      flextrack::io::convergence_plot_script("Mesh convergence: " + text, 1), "convergence.png");
      expect_harmless("bench_" + tag, "bench.gp", flextrack::io::bench_plot_script("Work-precision: " + text, 1),
                      "bench.png");
      // Probe names follow base::name_rule() today; the script does not rely on it.
      expect_harmless("deviation_" + tag, "deviation.gp", flextrack::io::deviation_plot_script({text}), "deviation.png");
      expect_harmless("run_" + tag, "run.gp", flextrack::io::run_plot_script("flextrack run " + text, {text}), "run.png");
      expect_harmless("run_no_probes_" + tag, "run.gp", flextrack::io::run_plot_script(text, {}), "run.png");
    }
}

// The hostile text arrives as the title: gnuplot prints it back unchanged (control characters as
// blanks), so the quoting neither lets it out nor mangles it.
TEST(Gnuplot, HostileTitleReadsBackAsText)
{
  ASSERT_TRUE(have_gnuplot()) << "gnuplot is a test dependency (.ci/setup installs gnuplot-nox)";
  const fs::path folder = data_folder("read_back");
  for (const std::string text : {"x'; system 'touch PWNED'; y='.prm", "`touch PWNED` @cmd \\'"})
    {
      std::ofstream(folder / "echo.gp") << "set print 'echo.txt'\nprint " << gnuplot_string(text) << "\n";
      std::string command = "cd '" + folder.string() + "' && gnuplot echo.gp";
      ASSERT_EQ(std::system(command.c_str()), 0);
      std::ifstream in(folder / "echo.txt");
      std::string line;
      std::getline(in, line);
      EXPECT_EQ(line, text);
      EXPECT_FALSE(fs::exists(folder / "PWNED"));
    }
  remove_data_folder(folder);
}

// A script that fails leaves no PNG and no temporary, and says so.
TEST(Gnuplot, FailedScriptLeavesNoPng)
{
  ASSERT_TRUE(have_gnuplot()) << "gnuplot is a test dependency (.ci/setup installs gnuplot-nox)";
  const fs::path folder = data_folder("failing");
  std::ofstream(folder / "bench.png") << "an older plot";
  std::ofstream(folder / "bad.gp") << "set terminal pngcairo\nset output png_file\nplot 'no_such_file.csv'\n";
  const auto result = flextrack::io::draw_png(folder.string(), "bad.gp", "bench.png");
  EXPECT_FALSE(result.drawn);
  EXPECT_NE(result.problem.find("gnuplot failed"), std::string::npos) << result.problem;
  EXPECT_FALSE(fs::exists(folder / "bench.png"));
  unsigned int files = 0;
  for ([[maybe_unused]] const auto &entry : fs::directory_iterator(folder)) ++files;
  EXPECT_EQ(files, 6u); // the five data files and bad.gp
  remove_data_folder(folder);
}

// A PNG cut short (a full disk: gnuplot still exits 0, bench.png was 4096 bytes) or not a PNG at
// all is refused and removed; the check is the PNG signature and the IEND chunk (PNG
// specification, ISO/IEC 15948, sections 5.2 and 11.2.5).
TEST(Gnuplot, IncompletePngIsRefused)
{
  ASSERT_TRUE(have_gnuplot()) << "gnuplot is a test dependency (.ci/setup installs gnuplot-nox)";
  const fs::path folder = data_folder("incomplete");
  std::ofstream(folder / "cut.gp") << "set terminal pngcairo size 900,620\nset output png_file\nplot sin(x)\n"
                                   << "unset output\nsystem(sprintf('truncate -s 4096 %s', png_file))\n";
  const auto cut = flextrack::io::draw_png(folder.string(), "cut.gp", "cut.png");
  EXPECT_FALSE(cut.drawn);
  EXPECT_NE(cut.problem.find("incomplete"), std::string::npos) << cut.problem;
  EXPECT_FALSE(fs::exists(folder / "cut.png"));
  std::ofstream(folder / "text.gp") << "set terminal dumb\nset output png_file\nplot sin(x)\n";
  const auto text = flextrack::io::draw_png(folder.string(), "text.gp", "text.png");
  EXPECT_FALSE(text.drawn);
  EXPECT_FALSE(fs::exists(folder / "text.png"));
  // The same script without the cut draws a whole PNG: the check is not what fails above.
  std::ofstream(folder / "whole.gp") << "set terminal pngcairo size 900,620\nset output png_file\nplot sin(x)\n";
  EXPECT_TRUE(flextrack::io::draw_png(folder.string(), "whole.gp", "whole.png").drawn);
  remove_data_folder(folder);
}
