// Small helpers for the text of parameter entries, written once for every stage:
//   trim("  a ")                       -> "a"
//   split("a, b,, c", ',')             -> {"a", "b", "c"}      (trimmed, empty items dropped)
//   named_items("a: 1; b: 2", ...)     -> {("a", "1"), ("b", "2")}
//   words("rigid, within 0.1")         -> {"rigid", "within", "0.1"}  (commas count as blanks)
//   parse_number("2.5", ...)           -> 2.5, or InputError; never nan or inf
//   parse_vector3("1, 0, 0", ...)      -> {1, 0, 0}, or InputError naming the entry
//   number_text(1e-10)                 -> "1e-10"
#pragma once

#include <base/names.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace flextrack::base
{
std::string trim(const std::string &text);

/// @p items joined by @p separator ("a, b, c").
std::string joined(const std::vector<std::string> &items, const std::string &separator = ", ");

/// Items of @p text separated by @p separator, trimmed; empty items are dropped.
std::vector<std::string> split(const std::string &text, char separator);

/// "NAME: SPEC; NAME: SPEC" -> (NAME, SPEC) pairs; every item needs its colon, else InputError
/// naming @p entry and the expected @p form.
std::vector<std::pair<std::string, std::string>> named_items(const std::string &text, const std::string &entry,
                                                             const std::string &form);

/// Blank- or comma-separated words.
std::vector<std::string> words(const std::string &text);

/// A finite number (the whole of @p word); InputError naming @p entry and saying @p what it is.
double parse_number(const std::string &word, const std::string &entry, const std::string &what);

/// A list of names ("a, b c"): each follows base::name_rule(), none is given twice; InputError
/// naming @p entry (@p what: "arm name", "body name", ...).
std::vector<std::string> parse_name_list(const std::string &text, const std::string &entry, const std::string &what);

/// @p x as a short text for messages (6 significant digits: "0.001", "1e-10", "inf").
std::string number_text(double x);

/// "x, y, z": three finite numbers separated by commas; InputError naming @p entry otherwise.
std::array<double, 3> parse_vector3(const std::string &text, const std::string &entry, const std::string &unit);
} // namespace flextrack::base
