// The one mapping from what a command throws to the process exit status and the error line:
// 2 = bad input (file, entry, allowed values), 3 = solver failure, 128 + N = stopped by signal N,
// 4 = internal error. main() prints the line; `flextrack sweep` records it for each case.
#pragma once

#include <functional>
#include <string>

namespace flextrack::app
{
struct CommandOutcome
{
  int status = 0;
  std::string message; ///< the error line without "flextrack: " ("error: ...", "solver failure: ..."); "" on success
};

/// Runs @p command and turns every error it throws into its exit status and line.
CommandOutcome run_guarded(const std::function<int()> &command);

/// Marks that the processes of the FE communicator work together from here on (a distributed
/// reduction): a failure on one of them must end all (main calls MPI_Abort), since the others
/// would wait for it in a collective step.
void start_collective_work();
bool collective_work_started();
} // namespace flextrack::app
