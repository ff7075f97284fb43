#include "isolated_run.h"

#include <base/input_error.h>
#include <base/parse_error.h>
#include <base/solver_error.h>

#include <deal.II/base/exceptions.h>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstring>
#include <exception>
#include <fstream>
#include <sstream>

#if defined(__SANITIZE_ADDRESS__)
#  define FLEXTRACK_FUZZ_ASAN 1
#elif defined(__has_feature)
#  if __has_feature(address_sanitizer)
#    define FLEXTRACK_FUZZ_ASAN 1
#  endif
#endif

namespace flextrack::fuzz
{
namespace
{
// Exit codes of the child; anything else (ASan and UBSan exit with 1) is a failure.
constexpr int exit_accepted = 0, exit_refused = 70, exit_internal = 71, exit_non_std = 72, exit_skipped = 73;

void write_message(const std::string &path, const std::string &message)
{
  std::ofstream(path, std::ios::trunc) << message.substr(0, 600);
}

[[noreturn]] void child(const ReaderTarget &target, const std::string &file, const std::string &directory, const double seconds,
                        const std::size_t memory_bytes, const std::string &message_file)
{
  // The wall-clock limit: SIGALRM's default action ends the process.
  itimerval limit{};
  limit.it_value.tv_sec = static_cast<time_t>(seconds);
  limit.it_value.tv_usec = static_cast<suseconds_t>(1e6 * (seconds - std::floor(seconds)));
  setitimer(ITIMER_REAL, &limit, nullptr);
#ifndef FLEXTRACK_FUZZ_ASAN
  const rlimit memory{memory_bytes, memory_bytes};
  setrlimit(RLIMIT_AS, &memory);
#else
  (void)memory_bytes;
#endif
  // The readers' progress output is not wanted; their errors (and sanitizer reports) are.
  if (const int null = open("/dev/null", O_WRONLY); null >= 0) dup2(null, STDOUT_FILENO);
  int status = exit_accepted;
  try
    {
      target.read(file, directory);
    }
  catch (const InputError &e)
    {
      write_message(message_file, e.what());
      status = exit_refused;
    }
  catch (const SolverError &e)
    {
      write_message(message_file, e.what());
      status = exit_refused;
    }
  catch (const dealii::ExceptionBase &e)
    {
      // Only deal.II's explanation, on one line (what() adds a banner and the source location).
      write_message(message_file, "deal.II: " + base::parse_error_text(e));
      status = exit_internal;
    }
  catch (const std::exception &e)
    {
      write_message(message_file, e.what());
      status = exit_internal;
    }
  catch (const NeedsReduction &)
    {
      status = exit_skipped;
    }
  catch (...)
    {
      status = exit_non_std;
    }
  // No destructors of static objects, no atexit handlers: the parent owns the process's state.
  _exit(status);
}
} // namespace

const char *kind_name(const Outcome::Kind kind)
{
  switch (kind)
    {
      case Outcome::Kind::accepted: return "accepted";
      case Outcome::Kind::refused: return "refused";
      case Outcome::Kind::internal_error: return "internal error";
      case Outcome::Kind::skipped: return "skipped";
      default: return "FAILURE";
    }
}

Outcome run_isolated(const ReaderTarget &target, const std::string &file, const std::string &directory,
                     const double seconds, const std::size_t memory_bytes, const std::string &work_dir)
{
  const std::string message_file = work_dir + "/child_message.txt";
  std::remove(message_file.c_str());
  std::fflush(nullptr); // nothing buffered may be written twice
  const pid_t pid = fork();
  if (pid < 0) return {Outcome::Kind::failure, std::string("fork failed: ") + std::strerror(errno)};
  if (pid == 0) child(target, file, directory, seconds, memory_bytes, message_file);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return {Outcome::Kind::failure, std::string("waitpid failed: ") + std::strerror(errno)};
  std::ifstream in(message_file);
  std::ostringstream message;
  message << in.rdbuf();
  if (WIFSIGNALED(status))
    {
      const int signal = WTERMSIG(status);
      if (signal == SIGALRM)
        {
          std::ostringstream d;
          d << "hang: still running after " << seconds << " s";
          return {Outcome::Kind::failure, d.str()};
        }
      return {Outcome::Kind::failure, std::string("crash: signal ") + std::to_string(signal) + " (" + strsignal(signal) + ")"};
    }
  switch (WEXITSTATUS(status))
    {
      case exit_accepted: return {Outcome::Kind::accepted, ""};
      case exit_refused: return {Outcome::Kind::refused, message.str()};
      case exit_internal: return {Outcome::Kind::internal_error, message.str()};
      case exit_skipped: return {Outcome::Kind::skipped, ""};
      case exit_non_std: return {Outcome::Kind::failure, "an exception not derived from std::exception"};
      default:
        return {Outcome::Kind::failure, "exit status " + std::to_string(WEXITSTATUS(status)) +
                                          " (a sanitizer report or exit() inside the reader; see its stderr)"};
    }
}
} // namespace flextrack::fuzz
