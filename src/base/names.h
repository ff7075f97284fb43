// Names that a user gives to things (arms, interfaces, output points; later bodies, joints,
// probes). They travel into other tools' inputs (MBDyn's .elm and .fem files, VTU/XML, HDF5 group
// paths, CSV headers), so they are restricted to a character set that needs no quoting anywhere:
// 1 to 64 ASCII letters, digits and '_'. The rule is checked where a name is created (the scene)
// and where it is read back (the reduced body file).
#pragma once

#include <string>

namespace flextrack::base
{
constexpr unsigned int max_name_length = 64;

inline bool is_valid_name(const std::string &name)
{
  if (name.empty() || name.size() > max_name_length) return false;
  for (const char c : name)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

/// The rule, for messages.
inline std::string name_rule() { return "1 to 64 characters, each an ASCII letter, a digit or '_'"; }

/// @p text cut to a short printable excerpt for a message: control and non-ASCII bytes shown as
/// '?', at most @p limit characters (then "...").
inline std::string printable_excerpt(const std::string &text, const std::size_t limit = 60)
{
  std::string out;
  for (const char c : text)
    {
      if (out.size() >= limit)
        {
          out += "...";
          break;
        }
      const auto u = static_cast<unsigned char>(c);
      out += (u < 0x20 || u >= 0x7f) ? '?' : c;
    }
  return out;
}
} // namespace flextrack::base
