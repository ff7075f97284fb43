#include <app/command_support.h>
#include <base/input_error.h>

#include <deal.II/base/mpi.h>

#include <sys/resource.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace flextrack::app
{
using namespace dealii;
namespace fs = std::filesystem;

std::string output_directory(const std::string &option, const std::string &scene_directory, const std::string &file)
{
  if (!option.empty()) return option;
  if (!scene_directory.empty()) return scene_directory;
  return "output/" + fs::path(file).stem().string();
}

void make_directory(const std::string &dir)
{
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw InputError("-o / Output/Directory", "cannot create the output folder '" + dir + "': " +
                                                (ec ? ec.message() : "a file of that name exists"));
}

double peak_memory_mib()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

std::string parameters_as_json(const ParameterHandler &prm)
{
  std::ostringstream s;
  prm.print_parameters(s, ParameterHandler::OutputStyle(ParameterHandler::JSON | ParameterHandler::Short));
  return s.str();
}

bool is_root() { return Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0; }

void write_text(const std::string &path, const std::string &text)
{
  if (!is_root()) return;
  std::ofstream out(path);
  out << text;
  if (!out) throw InputError("-o / Output/Directory", "cannot write '" + path + "'");
}

io::JsonObject timings_json(const TimerOutput &timer)
{
  io::JsonObject t;
  for (const auto &[name, seconds] : timer.get_summary_data(TimerOutput::total_wall_time)) t.add(name, seconds);
  return t;
}

std::string csv_number(const double v)
{
  std::ostringstream o;
  o << std::setprecision(12) << v;
  return o.str();
}
} // namespace flextrack::app
