#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>

#include <cmath>
#include <sstream>
#include <unordered_set>

namespace flextrack::base
{
std::string trim(const std::string &text)
{
  const auto a = text.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return text.substr(a, text.find_last_not_of(" \t\r\n") + 1 - a);
}

std::string joined(const std::vector<std::string> &items, const std::string &separator)
{
  std::string text;
  for (std::size_t i = 0; i < items.size(); ++i) text += (i ? separator : "") + items[i];
  return text;
}

std::vector<std::string> split(const std::string &text, const char separator)
{
  std::vector<std::string> items;
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, separator);)
    if (const auto t = trim(item); !t.empty()) items.push_back(t);
  return items;
}

std::vector<std::pair<std::string, std::string>> named_items(const std::string &text, const std::string &entry,
                                                             const std::string &form)
{
  std::vector<std::pair<std::string, std::string>> items;
  for (const auto &item : split(text, ';'))
    {
      const auto colon = item.find(':');
      if (colon == std::string::npos)
        throw InputError(entry, "'" + printable_excerpt(item) + "' is not of the form '" + form + "'");
      items.emplace_back(trim(item.substr(0, colon)), trim(item.substr(colon + 1)));
    }
  return items;
}

std::vector<std::string> words(const std::string &text)
{
  std::string blanks = text;
  for (auto &c : blanks)
    if (c == ',') c = ' ';
  std::istringstream in(blanks);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

double parse_number(const std::string &word, const std::string &entry, const std::string &what)
{
  const std::string t = trim(word);
  try
    {
      std::size_t used = 0;
      const double v = std::stod(t, &used);
      if (used == t.size() && std::isfinite(v)) return v;
    }
  catch (...)
    {
    }
  throw InputError(entry, "'" + printable_excerpt(t) + "' is not a finite number (" + what + ")");
}

std::vector<std::string> parse_name_list(const std::string &text, const std::string &entry, const std::string &what)
{
  std::vector<std::string> names;
  // A set for the repeat check: 200000 names took minutes pairwise, before any count limit.
  std::unordered_set<std::string> seen;
  for (const auto &name : words(text))
    {
      if (!is_valid_name(name))
        throw InputError(entry, what + " '" + printable_excerpt(name) + "' is not allowed: a name has " + name_rule());
      if (!seen.insert(name).second) throw InputError(entry, what + " '" + name + "' is listed twice");
      names.push_back(name);
    }
  return names;
}

std::array<double, 3> parse_vector3(const std::string &text, const std::string &entry, const std::string &unit)
{
  const auto items = split(text, ',');
  if (items.size() != 3)
    throw InputError(entry, "'" + printable_excerpt(text) + "' is not a vector 'x, y, z' of three numbers [" + unit + "]");
  std::array<double, 3> v{};
  for (unsigned int d = 0; d < 3; ++d) v[d] = parse_number(items[d], entry, "a component [" + unit + "]");
  return v;
}

std::string number_text(const double x)
{
  std::ostringstream m;
  m << x;
  return m.str();
}
} // namespace flextrack::base
