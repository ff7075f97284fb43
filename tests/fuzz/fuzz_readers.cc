// Fuzz driver for FlexTrack's readers of hostile input (issue 11, item 5): the scene reader, the
// Abaqus .inp and Gmsh .msh mesh readers and the reduced-body HDF5 reader (reader_targets.h).
//
// A simple mutation driver of our own (CI builds with g++ from Debian, without libFuzzer): it
// reads seed files, makes deterministic mutants of them (text_mutator.h, hdf5_mutator.h), and
// runs the reader on each mutant in a forked copy of itself (isolated_run.h). A reader may accept
// a mutant or refuse it with an exception the command line turns into one line (InputError,
// SolverError, or another std::exception: 'internal error', counted and listed separately).
// A signal, an abort, a sanitizer report, a hang beyond the per-input limit or an exception not
// derived from std::exception is a failure: the mutant is kept as WORK/TARGET-failure-N.EXT
// (path printed), to be added to tests/fuzz/regressions/, and the exit status is 1.
//
// Mutant N is a function of (--seed, N) only: a run with the same seeds, --seed and --runs makes
// the same mutants in the same order, whatever the machine's speed (--seconds only cuts the
// sequence short). The seeds themselves run first, unmodified.
//
// Budget: --seconds is for a Release build. A Debug + sanitizer build sets
// FLEXTRACK_TIME_LIMIT_FACTOR (8): the budget is divided by it (CI time stays bounded) and the
// per-input time limit multiplied by it (a slow build is not a hang).
//
// Usage:
//   fuzz_readers TARGET SEED... [--seconds S] [--runs N] [--seed K] [--timeout T] [--work DIR] [--verbose]
//     TARGET: scene, inp, msh, body; SEED: a file or a folder (its files with TARGET's endings);
//     --verbose prints every input's outcome and what was mutated
//   fuzz_readers --replay FOLDER [--directory DIR] [--timeout T] [--work DIR]
//     every file of FOLDER, unmodified, with the reader its ending names (.prm/.json, .inp,
//     .msh, .h5); fails if any crashes, hangs, reports or ends in an internal error (each must
//     be accepted or refused with a message). Scenes take relative file names from
//     DIR (default FOLDER): give the folder of the seed a kept input came from.
#include "hdf5_mutator.h"
#include "isolated_run.h"
#include "reader_targets.h"
#include "text_mutator.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace flextrack::fuzz;

namespace
{
struct Settings
{
  std::string target, replay, work = "fuzz_work";
  std::string directory; ///< --replay: relative file names in scenes are taken from here (default: FOLDER)
  std::vector<std::string> seed_paths;
  double seconds = 20, timeout = 10;
  long runs = 1000000;
  bool verbose = false; ///< --verbose: one line per input (outcome, what was mutated)
  std::uint64_t seed = 1;
  std::size_t memory_bytes = std::size_t(4) << 30; ///< address space of a child [bytes]
};

struct Seed
{
  std::string path, directory, text;
};

double time_limit_factor()
{
  const char *f = std::getenv("FLEXTRACK_TIME_LIMIT_FACTOR");
  const double factor = f ? std::atof(f) : 1.0;
  return factor >= 1 ? factor : 1.0;
}

[[noreturn]] void usage(const std::string &problem)
{
  std::cerr << "fuzz_readers: " << problem << "\n"
            << "usage: fuzz_readers TARGET SEED... [--seconds S] [--runs N] [--seed K] [--timeout T] [--work DIR] "
               "[--verbose]\n"
            << "       fuzz_readers --replay FOLDER [--directory DIR] [--timeout T] [--work DIR]\n"
            << "TARGET: scene, inp, msh, body" << std::endl;
  std::exit(2);
}

Settings parse(int argc, char **argv)
{
  Settings s;
  for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 == argc) usage(a + " needs a value");
        return argv[++i];
      };
      if (a == "--seconds") s.seconds = std::stod(value());
      else if (a == "--runs") s.runs = std::stol(value());
      else if (a == "--seed") s.seed = std::stoull(value());
      else if (a == "--timeout") s.timeout = std::stod(value());
      else if (a == "--work") s.work = value();
      else if (a == "--replay") s.replay = value();
      else if (a == "--directory") s.directory = value();
      else if (a == "--verbose") s.verbose = true;
      else if (a.rfind("--", 0) == 0) usage("unknown option " + a);
      else if (s.target.empty() && s.replay.empty()) s.target = a;
      else s.seed_paths.push_back(a);
    }
  if (s.replay.empty() && (s.target.empty() || s.seed_paths.empty())) usage("give a target and seeds, or --replay");
  return s;
}

std::string read_all(const std::string &path)
{
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The seed files: the files given, and the files of the folders given, that @p target reads;
/// sorted, so that mutant N is the same on every machine.
std::vector<Seed> collect_seeds(const ReaderTarget &target, const std::vector<std::string> &paths)
{
  std::vector<std::string> files;
  for (const auto &p : paths)
    {
      if (fs::is_directory(p))
        {
          for (const auto &e : fs::directory_iterator(p))
            if (e.is_regular_file() && target_for_file(e.path().string()) == &target) files.push_back(e.path().string());
        }
      else if (fs::is_regular_file(p))
        files.push_back(p);
      else
        usage("no seed file or folder " + p);
    }
  std::sort(files.begin(), files.end());
  files.erase(std::unique(files.begin(), files.end()), files.end());
  std::vector<Seed> seeds;
  for (const auto &f : files)
    {
      const auto parent = fs::path(f).parent_path().string();
      seeds.push_back({f, parent.empty() ? "." : parent, target.hdf5 ? "" : read_all(f)});
    }
  return seeds;
}

/// The random stream of mutant @p n: independent of every other mutant.
Rng stream_of(const std::uint64_t seed, const long n)
{
  Rng mix(seed * 0x9e3779b97f4a7c15ull + static_cast<std::uint64_t>(n));
  return Rng(mix.next());
}

struct Tally
{
  std::map<Outcome::Kind, long> counts;
  std::map<std::string, long> internal_errors; ///< message -> count
  long failures = 0;
};

void report(const std::string &what, const Outcome &o, Tally &tally)
{
  ++tally.counts[o.kind];
  if (o.kind == Outcome::Kind::internal_error) ++tally.internal_errors[o.detail.substr(0, 200)];
  if (o.kind == Outcome::Kind::failure)
    {
      ++tally.failures;
      std::cout << "FAILURE " << what << ": " << o.detail << std::endl;
    }
}

void print_summary(const std::string &name, const Tally &tally, const long runs, const double seconds)
{
  std::cout << name << ": " << runs << " inputs in " << seconds << " s";
  for (const auto kind : {Outcome::Kind::accepted, Outcome::Kind::refused, Outcome::Kind::internal_error,
                          Outcome::Kind::skipped, Outcome::Kind::failure})
    {
      const auto c = tally.counts.find(kind);
      std::cout << ", " << (c == tally.counts.end() ? 0 : c->second) << " " << kind_name(kind);
    }
  std::cout << std::endl;
  for (const auto &[message, count] : tally.internal_errors)
    std::cout << "  internal error (" << count << "x): " << message << std::endl;
}

/// Keeps the input @p source as WORK/TARGET-KIND-N.EXT; returns that path.
std::string keep_input(const Settings &s, const std::string &source, const std::string &kind, const std::string &extension,
                       const long n)
{
  const std::string kept = s.work + "/" + s.target + "-" + kind + "-" + std::to_string(n) + extension;
  fs::copy_file(source, kept, fs::copy_options::overwrite_existing);
  return kept;
}

int fuzz(const Settings &s)
{
  const ReaderTarget *target = find_target(s.target);
  if (!target) usage("unknown target '" + s.target + "'");
  const auto seeds = collect_seeds(*target, s.seed_paths);
  if (seeds.empty()) usage("no seed files for " + s.target);
  std::vector<std::string> donors;
  for (const auto &seed : seeds) donors.push_back(seed.text);
  const double factor = time_limit_factor(), budget = s.seconds / factor, timeout = s.timeout * factor;
  std::cout << "fuzz " << s.target << ": " << seeds.size() << " seeds, --seed " << s.seed << ", budget " << budget
            << " s (" << s.seconds << " s / time limit factor " << factor << "), " << timeout << " s per input"
            << std::endl;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  Tally tally;
  long n = 0;
  for (; n < s.runs && (n < static_cast<long>(seeds.size()) || elapsed() < budget); ++n)
    {
      // Inputs 0 ... seeds-1 are the seeds themselves; then mutants.
      Rng rng = stream_of(s.seed, n);
      const bool is_seed = n < static_cast<long>(seeds.size());
      const Seed &seed = is_seed ? seeds[n] : seeds[rng.below(seeds.size())];
      const std::string extension = fs::path(seed.path).extension().string();
      const std::string mutant = s.work + "/mutant" + extension;
      std::string description = is_seed ? "seed unchanged" : "";
      if (target->hdf5)
        {
          if (is_seed) fs::copy_file(seed.path, mutant, fs::copy_options::overwrite_existing);
          else description = mutate_hdf5(seed.path, mutant, rng);
        }
      else
        std::ofstream(mutant, std::ios::binary | std::ios::trunc)
          << (is_seed ? seed.text : mutate_text(seed.text, donors, rng));
      const Outcome o = run_isolated(*target, mutant, seed.directory, timeout, s.memory_bytes, s.work);
      std::ostringstream what;
      what << "input " << n << " (from " << seed.path << ": " << description << ")";
      report(what.str(), o, tally);
      if (s.verbose)
        std::cout << what.str() << ": " << kind_name(o.kind) << (o.detail.empty() ? "" : ": " + o.detail.substr(0, 200))
                  << std::endl;
      if (o.kind == Outcome::Kind::failure)
        std::cout << "  kept as " << keep_input(s, mutant, "failure", extension, n) << " (reproduce: fuzz_readers "
                  << "--replay on a folder holding it, --directory " << seed.directory << ")" << std::endl;
      // The first inputs of each distinct internal error too: not failures, but worth a look.
      if (o.kind == Outcome::Kind::internal_error && tally.internal_errors[o.detail.substr(0, 200)] <= 3)
        std::cout << "  internal error, kept as " << keep_input(s, mutant, "internal", extension, n) << " (from "
                  << seed.path << ")" << std::endl;
    }
  print_summary("fuzz " + s.target, tally, n, elapsed());
  return tally.failures ? 1 : 0;
}

int replay(const Settings &s)
{
  std::vector<std::string> files;
  for (const auto &e : fs::directory_iterator(s.replay))
    if (e.is_regular_file() && target_for_file(e.path().string())) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  const double timeout = s.timeout * time_limit_factor();
  Tally tally;
  for (const auto &f : files)
    {
      const Outcome o = run_isolated(*target_for_file(f), f, s.directory.empty() ? s.replay : s.directory, timeout,
                                     s.memory_bytes, s.work);
      std::cout << f << ": " << kind_name(o.kind) << (o.detail.empty() ? "" : ": " + o.detail.substr(0, 300)) << std::endl;
      report(f, o, tally);
    }
  print_summary("replay " + s.replay, tally, static_cast<long>(files.size()), 0);
  // A kept input must now be accepted or refused with a message: an internal error fails too.
  const auto internal = tally.counts.find(Outcome::Kind::internal_error);
  return tally.failures || internal != tally.counts.end() ? 1 : 0;
}
} // namespace

int main(int argc, char **argv)
{
  const Settings s = parse(argc, argv);
  fs::create_directories(s.work);
  return s.replay.empty() ? fuzz(s) : replay(s);
}
