// Ctrl-C and SIGTERM during a run (issue 25, item 9). The default action killed the process in
// the middle of writing: only `*.writing-PID` files were left, no results.h5, no summary.json.
// A run instead notes the signal, stops at its next output row, and writes what it has, like a
// solver failure; main() exits with 128 + the signal number, as a shell expects. A second signal
// ends the process at once.
#pragma once

#include <stdexcept>
#include <string>

#include <base/solver_error.h>

namespace flextrack::base
{
/// Handlers for SIGINT and SIGTERM that only note the signal (until stop_watching_interrupts()).
void watch_interrupts();
/// Restores the default action of both signals.
void stop_watching_interrupts();
/// The signal noted since watch_interrupts() (SIGINT or SIGTERM), or 0.
int interrupted();
/// "SIGINT" or "SIGTERM".
std::string signal_name(int signal);

/// A run stopped by a signal; what() says where, the results written up to then.
class Interrupted : public SolverError
{
public:
  Interrupted(int signal, const std::string &what) : SolverError(what), number(signal) {}
  int signal() const { return number; }

private:
  int number;
};
} // namespace flextrack::base
