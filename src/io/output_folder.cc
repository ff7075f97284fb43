#include <base/input_error.h>
#include <base/mpi_session.h>
#include <io/output_folder.h>

#include <charconv>
#include <stdexcept>
#include <system_error>

#include <mpi.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

namespace flextrack::io
{
namespace fs = std::filesystem;

namespace
{
const char *const folder_entry = "-o / Output/Directory";

std::string temporary_name(const std::string &path) { return path + ".writing-" + std::to_string(getpid()); }

/// Writes @p text to @p path; InputError with the system's reason (e.g. "No space left on device").
void write_file(const std::string &path, const std::string &text, const std::string &final_name)
{
  errno = 0;
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.flush();
  out.close();
  if (!out)
    throw InputError(folder_entry, "cannot write '" + final_name + "': " +
                                     (errno ? std::strerror(errno) : "write error") +
                                     " (is the disk full or the folder read-only?)");
}
} // namespace

bool is_first_process() { return base::fe_rank() == 0; }

void write_atomically(const std::string &path, const std::function<void(const std::string &)> &write)
{
  const std::string temporary = temporary_name(path);
  try
    {
      write(temporary);
      fs::rename(temporary, path);
    }
  catch (...)
    {
      std::error_code ignore;
      fs::remove(temporary, ignore);
      throw;
    }
}

std::string OutputFolder::choose(const std::string &option, const std::string &scene_directory, const std::string &file)
{
  if (!option.empty()) return option;
  if (!scene_directory.empty()) return scene_directory;
  return "output/" + fs::path(file).stem().string();
}

OutputFolder::OutputFolder(std::string path) : folder(std::move(path)) {}

void OutputFolder::create() const
{
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec || !fs::is_directory(folder))
    throw InputError(folder_entry, "cannot create the output folder '" + folder +
                                     "': " + (ec ? ec.message() : "a file of that name exists"));
}

OutputFolder::~OutputFolder()
{
  if (committed) return;
  std::error_code ignore;
  for (const auto &[temporary, name] : staged) fs::remove(temporary, ignore);
}

void OutputFolder::add_text(const std::string &name, const std::string &text)
{
  if (!is_first_process()) return;
  create();
  const std::string final_name = folder + "/" + name;
  const std::string temporary = temporary_name(final_name);
  staged.emplace_back(temporary, final_name);
  write_file(temporary, text, final_name);
}

std::string OutputFolder::add_file(const std::string &name)
{
  create();
  const std::string final_name = folder + "/" + name;
  staged.emplace_back(temporary_name(final_name), final_name);
  return staged.back().first;
}

void OutputFolder::tidy_previous_run(const std::string &command) { manifest = ".flextrack_" + command + "_files"; }

void OutputFolder::will_add(const std::string &name) { announced.push_back(name); }

std::vector<std::string> OutputFolder::commit()
{
  std::vector<std::string> names;
  for (const auto &[temporary, name] : staged)
    {
      std::error_code ec;
      if (!fs::exists(temporary, ec)) continue; // another process's file, or not written
      fs::rename(temporary, name, ec);
      if (ec) throw InputError(folder_entry, "cannot rename '" + temporary + "' to '" + name + "': " + ec.message());
      names.push_back(name);
    }
  committed = true;
  if (is_first_process() && !manifest.empty()) replace_manifest(names);
  return names;
}

void OutputFolder::replace_manifest(const std::vector<std::string> &written) const
{
  // The files of this run, by their names in the folder: those just renamed, and those a
  // program adds after the commit (a gnuplot PNG).
  std::set<std::string> now;
  for (const auto &path : written) now.insert(fs::path(path).filename().string());
  for (const auto &name : announced) now.insert(name);
  // Files the previous run wrote and this one did not (an animation, a deviation plot) would
  // sit beside this run's results as if they were its own: removed. Only names the manifest
  // lists are touched, never a user's own file in the folder.
  const std::string path = folder + "/" + manifest;
  std::ifstream previous(path);
  std::string name;
  while (std::getline(previous, name))
    if (!name.empty() && name.find('/') == std::string::npos && name != "." && name != ".." && !now.count(name))
      {
        std::error_code ignore;
        if (fs::is_regular_file(folder + "/" + name, ignore)) fs::remove(folder + "/" + name, ignore);
      }
  previous.close();
  std::ostringstream list;
  for (const auto &n : now) list << n << "\n";
  try
    {
      write_atomically(path, [&](const std::string &temporary) { write_file(temporary, list.str(), path); });
    }
  catch (const InputError &)
    {
      // The results are committed; without a manifest the next run only cannot tidy up.
    }
}

void OutputFolder::add_frequencies(const std::vector<double> &frequencies_hz)
{
  std::ostringstream csv;
  csv << "mode,frequency_Hz\n";
  for (std::size_t k = 0; k < frequencies_hz.size(); ++k) csv << k + 1 << "," << csv_number(frequencies_hz[k]) << "\n";
  add_text("frequencies.csv", csv.str());
}

void OutputFolder::add_parameters(const dealii::ParameterHandler &prm)
{
  std::ostringstream used;
  prm.print_parameters(used, dealii::ParameterHandler::OutputStyle(dealii::ParameterHandler::PRM |
                                                                     dealii::ParameterHandler::Short));
  add_text("parameters_used.prm", used.str());
}

void OutputFolder::add_summary(const JsonObject &summary) { add_text("summary.json", summary.str() + "\n"); }

std::string parameters_as_json(const dealii::ParameterHandler &prm)
{
  std::ostringstream s;
  prm.print_parameters(s, dealii::ParameterHandler::OutputStyle(dealii::ParameterHandler::JSON |
                                                                 dealii::ParameterHandler::Short));
  return s.str();
}

JsonObject timings_json(const dealii::TimerOutput &timer)
{
  JsonObject t;
  for (const auto &[name, seconds] : timer.get_summary_data(dealii::TimerOutput::total_wall_time)) t.add(name, seconds);
  return t;
}

double peak_memory_mib()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

std::string csv_number(const double v)
{
  // What an ostream with setprecision(12) writes, printf's %.12g (std::to_chars with a precision
  // is specified as that), without building a stream for every number: a run writes tens of
  // them per output row.
  char text[40];
  const auto [end, error] = std::to_chars(text, text + sizeof(text), v, std::chars_format::general, 12);
  if (error != std::errc()) throw std::logic_error("csv_number: no room for the text of a number");
  return std::string(text, end);
}
} // namespace flextrack::io
