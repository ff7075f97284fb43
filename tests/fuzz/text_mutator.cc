#include "text_mutator.h"

#include <algorithm>
#include <cctype>
#include <functional>
#include <utility>

namespace flextrack::fuzz
{
std::uint64_t Rng::next()
{
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

const std::vector<std::string> &hostile_numbers()
{
  static const std::vector<std::string> values{
    "0",          "-0",          "-1",          "1e308",        "-1e308",      "1e309",
    "-1e309",     "nan",         "NaN",         "-nan",         "inf",         "-inf",
    "Infinity",   "1e-320",      "4.9e-324",    "2147483647",   "2147483648",  "-2147483648",
    "-2147483649", "4294967295", "4294967296",  "9223372036854775807", "9223372036854775808",
    "-9223372036854775809", "18446744073709551616", "99999999999999999999999999999", "0x10",
    "1e9",        "1e-9",        "3",           "1.5",          "-3.5",        "1e",
    "--1",        "1..2",        "+",           "",             "1,2",         "1 2"};
  return values;
}

namespace
{
/// Where the tokens (maximal runs of characters other than white space and , ; = { } [ ] ")
/// of @p text are: (start, length).
std::vector<std::pair<std::size_t, std::size_t>> tokens(const std::string &text)
{
  auto separator = [](const char c) {
    return std::isspace(static_cast<unsigned char>(c)) || std::string(",;={}[]\":").find(c) != std::string::npos;
  };
  std::vector<std::pair<std::size_t, std::size_t>> t;
  for (std::size_t i = 0; i < text.size();)
    {
      if (separator(text[i]))
        {
          ++i;
          continue;
        }
      const std::size_t start = i;
      while (i < text.size() && !separator(text[i])) ++i;
      t.emplace_back(start, i - start);
    }
  return t;
}

bool looks_numeric(const std::string &text, std::size_t start, std::size_t length)
{
  const char c = text[start];
  return std::isdigit(static_cast<unsigned char>(c)) ||
         ((c == '-' || c == '+' || c == '.') && length > 1 && std::isdigit(static_cast<unsigned char>(text[start + 1])));
}

std::vector<std::string> lines_of(const std::string &text)
{
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size())
    {
      const std::size_t end = text.find('\n', start);
      if (end == std::string::npos)
        {
          lines.push_back(text.substr(start));
          break;
        }
      lines.push_back(text.substr(start, end - start + 1));
      start = end + 1;
    }
  return lines;
}

std::string joined(const std::vector<std::string> &lines)
{
  std::string text;
  for (const auto &l : lines) text += l;
  return text;
}

void flip_bits(std::string &s, Rng &rng)
{
  if (s.empty()) return;
  for (std::size_t k = 1 + rng.below(8); k > 0; --k) s[rng.below(s.size())] ^= static_cast<char>(1u << rng.below(8));
}

void insert_bytes(std::string &s, Rng &rng)
{
  // Bytes that mean something to one of the formats, and arbitrary ones.
  static const char bytes_that_mean_something[] = "\0\n\r\t ,;=#{}[]\"\\*$-.eE0123456789";
  static const std::string meaningful(bytes_that_mean_something, sizeof(bytes_that_mean_something) - 1);
  std::string bytes;
  for (std::size_t k = 1 + rng.below(8); k > 0; --k)
    bytes += rng.one_in(2) ? meaningful[rng.below(meaningful.size())] : static_cast<char>(rng.below(256));
  s.insert(rng.below(s.size() + 1), bytes);
}

void delete_bytes(std::string &s, Rng &rng)
{
  if (s.empty()) return;
  const std::size_t at = rng.below(s.size());
  s.erase(at, 1 + rng.below(16));
}

void duplicate_token(std::string &s, Rng &rng)
{
  const auto t = tokens(s);
  if (t.empty()) return;
  const auto [start, length] = t[rng.below(t.size())];
  const std::string token = s.substr(start, length);
  std::string copies;
  const std::size_t n = rng.one_in(8) ? 1 + rng.below(1000) : 1;
  for (std::size_t k = 0; k < n; ++k) copies += (rng.one_in(2) ? " " : ",") + token;
  s.insert(rng.one_in(2) ? start + length : rng.below(s.size() + 1), copies);
}

void replace_number(std::string &s, Rng &rng)
{
  std::vector<std::pair<std::size_t, std::size_t>> numbers;
  for (const auto &t : tokens(s))
    if (looks_numeric(s, t.first, t.second)) numbers.push_back(t);
  if (numbers.empty()) return;
  const auto [start, length] = numbers[rng.below(numbers.size())];
  const auto &values = hostile_numbers();
  s.replace(start, length, values[rng.below(values.size())]);
}

void truncate(std::string &s, Rng &rng) { s.resize(rng.below(s.size() + 1)); }

void shuffle_lines(std::string &s, Rng &rng)
{
  auto lines = lines_of(s);
  if (lines.empty()) return;
  const std::size_t a = rng.below(lines.size()), b = rng.below(lines.size());
  switch (rng.below(4))
    {
      case 0: std::swap(lines[a], lines[b]); break;
      case 1: lines.insert(lines.begin() + b, lines[a]); break;
      case 2: lines.erase(lines.begin() + a); break;
      default:
        {
          // A whole range moved: sections and subsections end up interleaved.
          const std::size_t from = std::min(a, b), to = std::max(a, b) + 1;
          std::vector<std::string> block(lines.begin() + from, lines.begin() + to);
          lines.erase(lines.begin() + from, lines.begin() + to);
          const std::size_t at = rng.below(lines.size() + 1);
          lines.insert(lines.begin() + at, block.begin(), block.end());
        }
    }
  s = joined(lines);
}

void splice_donor(std::string &s, const std::vector<std::string> &donors, Rng &rng)
{
  if (donors.empty()) return;
  const auto donor = lines_of(donors[rng.below(donors.size())]);
  if (donor.empty()) return;
  const std::size_t from = rng.below(donor.size()), n = 1 + rng.below(std::min<std::size_t>(donor.size() - from, 20));
  auto lines = lines_of(s);
  const std::size_t at = rng.below(lines.size() + 1);
  lines.insert(lines.begin() + at, donor.begin() + from, donor.begin() + from + n);
  s = joined(lines);
}
} // namespace

std::string mutate_text(const std::string &text, const std::vector<std::string> &donors, Rng &rng,
                        const std::size_t max_bytes)
{
  // Weights: the structure-aware mutations (numbers, tokens, lines) find more than bit noise
  // in these formats, whose readers refuse most random bytes at the first line.
  const std::vector<std::pair<int, std::function<void(std::string &)>>> operations{
    {2, [&](std::string &s) { flip_bits(s, rng); }},
    {2, [&](std::string &s) { insert_bytes(s, rng); }},
    {2, [&](std::string &s) { delete_bytes(s, rng); }},
    {3, [&](std::string &s) { duplicate_token(s, rng); }},
    {6, [&](std::string &s) { replace_number(s, rng); }},
    {1, [&](std::string &s) { truncate(s, rng); }},
    {3, [&](std::string &s) { shuffle_lines(s, rng); }},
    {1, [&](std::string &s) { splice_donor(s, donors, rng); }}};
  int total = 0;
  for (const auto &o : operations) total += o.first;
  std::string s = text;
  for (std::size_t k = 1 + rng.below(4); k > 0; --k)
    {
      int pick = static_cast<int>(rng.below(total));
      for (const auto &o : operations)
        if ((pick -= o.first) < 0)
          {
            o.second(s);
            break;
          }
      if (s.size() > max_bytes) s.resize(max_bytes);
    }
  return s;
}
} // namespace flextrack::fuzz
