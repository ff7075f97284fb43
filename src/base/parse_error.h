// deal.II's parameter-file errors carry their explanation in print_info(); this keeps only that,
// on one line, for an InputError. deal.II quotes the offending value whole: a value of a
// megabyte would make a megabyte of message, so it is cut to a short printable excerpt that
// says how long it was (the entry's name, after it, stays readable).
#pragma once

#include <base/names.h>
#include <base/text.h>

#include <deal.II/base/exceptions.h>

#include <sstream>
#include <string>

namespace flextrack::base
{
inline std::string parse_error_text(const dealii::ExceptionBase &e)
{
  std::ostringstream s;
  e.print_info(s);
  std::string text;
  for (const char c : s.str())
    {
      const char d = c == '\n' ? ' ' : c;
      if (!(d == ' ' && !text.empty() && text.back() == ' ')) text += d;
    }
  // "The entry value VALUE for the entry named NAME does not match ...": VALUE may be huge.
  const std::string value_start = "The entry value ", value_end = " for the entry named ";
  const std::size_t v = text.find(value_start), end = v == std::string::npos ? v : text.find(value_end, v);
  if (end != std::string::npos)
    {
      const std::size_t from = v + value_start.size();
      const std::string value = text.substr(from, end - from);
      if (value.size() > 80)
        text = text.substr(0, from) + "'" + printable_excerpt(value, 40) + "' (" + std::to_string(value.size()) +
               " characters)" + text.substr(end);
    }
  // deal.II's "Line <18> of file <input string>: " names the expanded scene text, not a file.
  const std::string noise = "of file <input string>";
  if (const std::size_t n = text.find(noise); n != std::string::npos) text.replace(n, noise.size(), "of the scene");
  return trim(text);
}
} // namespace flextrack::base
