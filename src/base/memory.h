// Resident memory of the process: what large FE runs are limited by.
//  - probe_memory: with the environment variable FLEXTRACK_MEMORY_PROBE set, prints the peak and
//    current resident memory (VmHWM, VmRSS of /proc/self/status) at a named stage to stderr, to
//    find where a run's memory goes; without it, does nothing.
//  - release_free_heap: hands the heap's free pages back to the system. Sparsity patterns,
//    Epetra's row-wise scratch and the workspace of a fill-reducing ordering are many small
//    blocks; freed, glibc keeps them resident (it returns only the top of the heap by itself),
//    and a factorisation that follows would add its factor on top of them.
//  - check_memory_for: refuses, before it starts, a step (a factorisation, assembling a body)
//    whose estimated size will not fit in the memory the machine has left, with a message that
//    says what would fit.
#pragma once

#include <base/mpi_session.h>
#include <base/solver_error.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace flextrack::base
{
inline void probe_memory(const char *stage)
{
  static const bool enabled = std::getenv("FLEXTRACK_MEMORY_PROBE") != nullptr;
  if (!enabled) return;
  std::ifstream status("/proc/self/status");
  std::string line, peak, now;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0)
      peak = line.substr(6);
    else if (line.rfind("VmRSS:", 0) == 0)
      now = line.substr(6);
  std::cerr << "memory at " << stage << ": peak" << peak << ", now" << now << std::endl;
}

inline void release_free_heap()
{
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

namespace memory_detail
{
/// The first number of @p file after @p key (a line "key value"), or -1.
inline double read_number(const char *file, const std::string &key = "")
{
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0)
      {
        std::istringstream rest(line.substr(key.size()));
        double value = -1;
        return (rest >> value) ? value : -1;
      }
  return -1;
}
} // namespace memory_detail

/// Resident memory of this process now [bytes].
inline double resident_bytes() { return 1024.0 * std::max(0.0, memory_detail::read_number("/proc/self/status", "VmRSS:")); }

/// Memory this machine can still give [bytes]: MemAvailable of /proc/meminfo, capped by the
/// control group's limit (a batch job's share: cgroup v2 memory.max less memory.current) and by
/// the environment variable FLEXTRACK_MEMORY_LIMIT (GiB that FlexTrack's processes on this
/// machine may use in all) less @p used_here [bytes], what they hold already.
inline double available_memory_bytes(const double used_here)
{
  double available = 1024.0 * memory_detail::read_number("/proc/meminfo", "MemAvailable:");
  if (!(available > 0)) available = HUGE_VAL;
  // The process' own control group (cgroup v2: the line "0::/path" of /proc/self/cgroup), where
  // a batch system puts a job's limit, and the root's.
  std::string group;
  {
    std::ifstream in("/proc/self/cgroup");
    std::string line;
    while (std::getline(in, line))
      if (line.rfind("0::", 0) == 0) group = line.substr(3);
  }
  for (const std::string &folder : {"/sys/fs/cgroup" + group, std::string("/sys/fs/cgroup")})
    {
      const double limit = memory_detail::read_number((folder + "/memory.max").c_str()); // -1 for "max"
      const double current = memory_detail::read_number((folder + "/memory.current").c_str());
      if (limit > 0 && current >= 0) available = std::min(available, limit - current);
    }
  if (const char *cap = std::getenv("FLEXTRACK_MEMORY_LIMIT"); cap && *cap)
    {
      char *end = nullptr;
      const double gib = std::strtod(cap, &end);
      if (end != cap && gib > 0) available = std::min(available, gib * 1073741824.0 - used_here);
    }
  return std::max(available, 0.0);
}

/// What a memory check is about: data the processes share (a factor, a distributed model: each
/// holds its part, so more machines help), or data every process holds whole (only fewer
/// processes per machine help).
enum class MemoryUse { shared_factor, replicated };

/// Refuses a step that needs about @p bytes more on this process: throws SolverError, with what
/// would fit, when the processes of one machine together need more than it has available. With
/// @p communicator (a collective step: every process of it calls this), the machines are the
/// shared-memory groups of its processes and every process throws the same error; without it,
/// this process alone is checked.
inline void check_memory_for(const std::string &what, const double bytes, const MPI_Comm *communicator = nullptr,
                             const MemoryUse use = MemoryUse::shared_factor)
{
  constexpr double GiB = 1073741824.0;
  int n_processes = 1;
  double need_here = bytes, used_here = resident_bytes(), per_process = bytes, total = bytes, available = 0;
  double on_machine = 1; // processes on the machine that lacks most
  bool collective = communicator && fe_processes() > 1;
  if (collective) MPI_Comm_size(*communicator, &n_processes);
  collective = collective && n_processes > 1;
  if (collective)
    {
      MPI_Comm machine;
      MPI_Comm_split_type(*communicator, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &machine);
      MPI_Allreduce(&bytes, &need_here, 1, MPI_DOUBLE, MPI_SUM, machine);
      const double mine = resident_bytes();
      MPI_Allreduce(&mine, &used_here, 1, MPI_DOUBLE, MPI_SUM, machine);
      int here = 1;
      MPI_Comm_size(machine, &here);
      MPI_Comm_free(&machine);
      available = available_memory_bytes(used_here);
      // The machine that lacks most decides; every process reports its numbers.
      double shortfall = need_here - available, worst = 0;
      MPI_Allreduce(&shortfall, &worst, 1, MPI_DOUBLE, MPI_MAX, *communicator);
      const bool mine_decides = shortfall == worst;
      double values[5] = {mine_decides ? need_here : 0, mine_decides ? available : 0, bytes,
                          mine_decides ? used_here : 0, mine_decides ? double(here) : 0};
      double global[5];
      MPI_Allreduce(values, global, 5, MPI_DOUBLE, MPI_MAX, *communicator);
      need_here = global[0];
      available = global[1];
      per_process = global[2];
      used_here = global[3];
      on_machine = global[4];
      MPI_Allreduce(&bytes, &total, 1, MPI_DOUBLE, MPI_SUM, *communicator);
    }
  else
    available = available_memory_bytes(used_here);
  if (need_here <= available) return;
  std::ostringstream m;
  m.precision(3);
  m << what << " needs about " << per_process / GiB << " GiB per process with " << n_processes << " process"
    << (n_processes > 1 ? "es" : "") << " (" << need_here / GiB << " GiB on one machine, where the processes hold "
    << used_here / GiB << " GiB already), but only " << available / GiB << " GiB are available there; it was not started. ";
  // Advice from each process' footprint, what it holds plus what it needs, against what one
  // machine like this gives FlexTrack's processes (available plus what they hold now): how many
  // processes fit on one such machine, so how many machines the run needs.
  const double machine = available + used_here;
  const double footprint = (used_here + need_here) / on_machine;
  const double fit = footprint > 0 ? std::floor(machine / footprint) : 0;
  const double machines_for_one = available > 0 ? std::ceil(total / available) : 0; // one process: its share per machine
  if (use == MemoryUse::replicated && n_processes > 1)
    m << "Every process holds all of it: run fewer processes on each machine, or run ";
  else if (use == MemoryUse::shared_factor && n_processes == 1 && available > 1e-3 * total && machines_for_one > 1)
    m << "It is about " << total / GiB << " GiB; under MPI the processes share it: run on about " << machines_for_one
      << " machines like this one, one process on each (mpirun), or run ";
  else if (use == MemoryUse::shared_factor && available > 0 && n_processes > 1 && fit >= 1 && fit < on_machine)
    m << "Each process needs about " << footprint / GiB << " GiB in all, and a machine like this one holds "
      << fit << " such process" << (fit > 1 ? "es" : "") << ": run on about " << std::ceil(n_processes / fit)
      << " machines like this one, " << fit << " process" << (fit > 1 ? "es" : "") << " on each (mpirun), or run ";
  else if (use == MemoryUse::shared_factor && n_processes > 1 && available > 1e-3 * total)
    m << "It is about " << total / GiB << " GiB in all, which the processes share: run with more processes on about "
      << std::max(2.0, std::ceil((total + used_here * n_processes / on_machine) / machine))
      << " machines like this one (mpirun), or run ";
  else
    m << "Free memory on this machine, or run ";
  m << "on a machine with more memory, or with a coarser mesh (FLEXTRACK_MEMORY_LIMIT [GiB], if set, caps the "
       "memory assumed available)";
  throw SolverError(m.str());
}
} // namespace flextrack::base
