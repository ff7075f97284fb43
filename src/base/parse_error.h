// deal.II's parameter-file errors carry their explanation in print_info(); this keeps only that,
// on one line, for an InputError.
#pragma once

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
  return text;
}
} // namespace flextrack::base
