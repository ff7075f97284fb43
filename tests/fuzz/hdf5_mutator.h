// Deterministic mutations of HDF5 files (reduced bodies) for the fuzz driver fuzz_readers.cc.
// Two kinds: structural ones through the HDF5 C API (values of datasets and attributes replaced
// by hostile numbers and texts, shapes and types changed, objects deleted or copied under a new
// name), which keep the file readable as HDF5 and so reach the reader's own checks; and byte
// mutations of the file (bit flips, overwritten runs, truncation), which test what the HDF5
// library and the reader do with a damaged file.
#pragma once

#include "text_mutator.h"

#include <string>

namespace flextrack::fuzz
{
/// Writes to @p mutant a mutated copy of the HDF5 file @p seed. Returns a one-line description
/// of what was changed (printed with a failing input).
std::string mutate_hdf5(const std::string &seed, const std::string &mutant, Rng &rng);
} // namespace flextrack::fuzz
