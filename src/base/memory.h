// Resident memory of the process: what large FE runs are limited by.
//  - probe_memory: with the environment variable FLEXTRACK_MEMORY_PROBE set, prints the peak and
//    current resident memory (VmHWM, VmRSS of /proc/self/status) at a named stage to stderr, to
//    find where a run's memory goes; without it, does nothing.
//  - release_free_heap: hands the heap's free pages back to the system. Sparsity patterns,
//    Epetra's row-wise scratch and the workspace of a fill-reducing ordering are many small
//    blocks; freed, glibc keeps them resident (it returns only the top of the heap by itself),
//    and a factorisation that follows would add its factor on top of them.
#pragma once

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
} // namespace flextrack::base
