// Runs one reader on one input in a forked copy of the fuzz driver, so that a crash, an abort, a
// sanitizer report or a hang ends that copy only and is seen by the driver as an outcome. The
// reader code is the same in-process code the command line runs (no exec, no separate program);
// the driver itself never calls a reader, so no library state (threads, HDF5 handles) is
// inherited mid-use by the copy.
#pragma once

#include "reader_targets.h"

#include <string>

namespace flextrack::fuzz
{
struct Outcome
{
  enum class Kind
  {
    accepted,       ///< the reader returned a value
    refused,        ///< InputError or SolverError: the command line's one-line error, exit 2 or 3
    internal_error, ///< another std::exception: the command line's one line "internal error", exit 4
    skipped,        ///< the scene would reduce a flexible body (reader_targets.h)
    failure         ///< a signal, a sanitizer report, a hang, a non-std exception
  };
  Kind kind;
  std::string detail; ///< the exception's message, or what the failure was
};

/// Runs @p target's reader on @p file in a child process that may take @p seconds of wall time
/// (then it is a hang) and, unless built with AddressSanitizer (which reserves terabytes of
/// address space), @p memory_bytes of address space (beyond it allocation throws std::bad_alloc).
/// @p work_dir receives the child's message file.
Outcome run_isolated(const ReaderTarget &target, const std::string &file, const std::string &directory,
                     double seconds, std::size_t memory_bytes, const std::string &work_dir);

const char *kind_name(Outcome::Kind kind);
} // namespace flextrack::fuzz
