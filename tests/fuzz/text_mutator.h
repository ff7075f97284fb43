// Deterministic mutations of text inputs (scene files, .inp and .msh meshes) for the fuzz
// driver fuzz_readers.cc. Every mutant is a function of (seed text, random stream) only, and the
// random stream is our own (splitmix64, with our own reduction to a range), so the same
// --seed gives the same mutants with any standard library.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace flextrack::fuzz
{
/// splitmix64 (Steele, Lea, Flood 2014): small, fast, and fully specified, unlike the
/// distributions of <random>, whose output differs between standard libraries.
class Rng
{
public:
  explicit Rng(std::uint64_t seed) : state(seed) {}
  std::uint64_t next();
  /// Uniform-ish in [0, n) for n > 0 (the modulo bias is irrelevant here).
  std::size_t below(std::size_t n) { return n == 0 ? 0 : next() % n; }
  bool one_in(std::size_t n) { return below(n) == 0; }

private:
  std::uint64_t state;
};

/// Values that break naive number handling: overflow, NaN, infinities, signs, integer limits,
/// denormals, non-decimal spellings.
const std::vector<std::string> &hostile_numbers();

/// Applies 1 to 4 stacked mutations to @p text: bit flips, byte insertion and deletion, token
/// duplication, number replacement by a hostile number, truncation, line swaps, duplications,
/// deletions, and splicing lines of another seed from @p donors. The result is at most
/// @p max_bytes long.
std::string mutate_text(const std::string &text, const std::vector<std::string> &donors, Rng &rng,
                        std::size_t max_bytes = 1u << 20);
} // namespace flextrack::fuzz
