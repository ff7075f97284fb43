// Entries set on the command line (parameter_overrides.h).
#include <base/input_error.h>
#include <base/parse_error.h>
#include <base/text.h>
#include <io/parameter_overrides.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <functional>
#include <optional>
#include <regex>
#include <sstream>

namespace flextrack::io
{
namespace
{
using Tree = boost::property_tree::ptree;

/// Every declared entry and subsection of @p prm (deal.II 9.4 prints JSON with its keys demangled:
/// "Probe bob_centre"); an entry is a node with a "value",
/// marked "entry", or "file entry" when its pattern is a FileName.
Tree declared_tree(const dealii::ParameterHandler &prm)
{
  std::stringstream json;
  prm.print_parameters(json, dealii::ParameterHandler::JSON);
  Tree raw;
  boost::property_tree::read_json(json, raw);
  const std::function<Tree(const Tree &)> clean = [&](const Tree &node) {
    Tree out;
    for (const auto &[key, child] : node)
      {
        if (child.count("value"))
          {
            const bool file = child.get<std::string>("pattern_description", "").find("[FileName") == 0;
            out.push_back({key, Tree(file ? "file entry" : "entry")});
          }
        else if (!child.empty())
          out.push_back({key, clean(child)});
      }
    return out;
  };
  return clean(raw);
}

bool is_entry(const Tree &node) { return node.empty() && (node.data() == "entry" || node.data() == "file entry"); }

/// The subsections and the entry of @p path in @p tree: the longest chain of subsections that
/// leaves an entry name (which may itself hold a '/'); nothing if there is no such entry.
struct Resolved
{
  std::vector<std::string> subsections;
  std::string entry;
  std::string deepest; ///< the deepest subsection reached ('/'-joined), for "did you mean"
  std::string missing; ///< the name not found there
};
Resolved resolve(const Tree &tree, const std::string &path)
{
  Resolved r;
  const Tree *node = &tree;
  std::string rest = path;
  for (;;)
    {
      if (const auto it = node->find(rest); it != node->not_found() && is_entry(it->second))
        {
          r.entry = rest;
          return r;
        }
      const auto slash = rest.find('/');
      const std::string head = rest.substr(0, slash);
      const auto it = node->find(head);
      if (slash == std::string::npos || it == node->not_found() || is_entry(it->second))
        {
          r.missing = head;
          return r;
        }
      r.subsections.push_back(head);
      r.deepest += (r.deepest.empty() ? "" : "/") + head;
      node = &it->second;
      rest = rest.substr(slash + 1);
    }
}

unsigned int edit_distance(const std::string &a, const std::string &b)
{
  std::vector<unsigned int> row(b.size() + 1);
  for (unsigned int j = 0; j <= b.size(); ++j) row[j] = j;
  for (unsigned int i = 1; i <= a.size(); ++i)
    {
      unsigned int diagonal = row[0];
      row[0] = i;
      for (unsigned int j = 1; j <= b.size(); ++j)
        {
          const unsigned int up = row[j];
          const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                            std::tolower(static_cast<unsigned char>(b[j - 1]));
          row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
          diagonal = up;
        }
    }
  return row[b.size()];
}

std::vector<std::string> nearest_in(const Tree &tree, const std::string &path, const std::string &name)
{
  const Tree *node = &tree;
  std::istringstream parts(path);
  std::string part;
  while (!path.empty() && std::getline(parts, part, '/'))
    {
      const auto it = node->find(part);
      if (it == node->not_found()) return {};
      node = &it->second;
    }
  std::vector<std::pair<unsigned int, std::string>> scored;
  for (const auto &[key, child] : *node)
    {
      const unsigned int d = edit_distance(name, key);
      const bool same_start = name.size() >= 4 && key.compare(0, 4, name, 0, 4) == 0;
      if (d <= 3 || same_start) scored.emplace_back(d, key);
    }
  std::sort(scored.begin(), scored.end());
  std::vector<std::string> names;
  for (std::size_t i = 0; i < scored.size() && i < 5; ++i) names.push_back(scored[i].second);
  return names;
}

/// "; nearest declared: 'a', 'b' (...)", or only the pointer to print-parameters.
std::string hint_text(const std::vector<std::string> &names)
{
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", '" : "'") + names[i] + "'";
  return (s.empty() ? std::string() : "; nearest declared: " + s) + " (flextrack print-parameters lists every entry)";
}
} // namespace

std::string explained_pattern_mismatch(const std::string &message)
{
  std::smatch m;
  if (!std::regex_search(message, m, std::regex(R"(The entry value (.*) for the entry named (.*) does not match the given pattern: \[(.*) \])")))
    return "";
  const std::string value = m[1], entry = m[2], pattern = m[3];
  if (pattern.rfind("Selection ", 0) == 0)
    {
      std::string allowed = pattern.substr(10);
      for (std::size_t i = 0; (i = allowed.find('|', i)) != std::string::npos;) allowed.replace(i, 1, ", ");
      return "entry '" + entry + "' is '" + value + "'; allowed: " + allowed;
    }
  return "entry '" + entry + "' is '" + value + "', which is not " + (pattern == "Bool" ? "true or false" : "a " + pattern);
}

ParameterOverride parse_override(const std::string &text)
{
  const auto fail = [&](const std::string &why) {
    throw InputError("--set", "'" + base::printable_excerpt(text, 200) + "': " + why);
  };
  const auto equals = text.find('=');
  if (equals == std::string::npos) fail("expected ENTRY=VALUE, e.g. --set \"Multibody/End time=5\"");
  ParameterOverride o;
  std::string path = base::trim(text.substr(0, equals));
  o.value = base::trim(text.substr(equals + 1));
  // "Body NAME:PATH": an entry of that flexible body's body scene.
  if (const auto colon = path.find(':'); colon != std::string::npos)
    {
      o.scope = base::trim(path.substr(0, colon));
      path = base::trim(path.substr(colon + 1));
      if (o.scope.rfind("Body ", 0) != 0 || base::trim(o.scope.substr(5)).empty())
        fail("the part before ':' must name a flexible body of the scene, 'Body NAME' (its body scene's entry "
             "follows the ':')");
    }
  // Blanks around the '/' are not part of the names.
  std::string cleaned;
  std::istringstream parts(path);
  std::string part;
  while (std::getline(parts, part, '/')) cleaned += (cleaned.empty() ? "" : "/") + base::trim(part);
  o.path = cleaned;
  if (o.path.empty() || o.path.back() == '/' || o.path.find("//") != std::string::npos)
    fail("the entry is empty; expected SUBSECTION/.../ENTRY as print-parameters shows it");
  for (const char c : o.path + o.value)
    if (c == '\n' || c == '\r' || c == '#' || c == '\0')
      fail("a line break, '#' or a NUL character is not allowed in an entry or value set on the command line");
  if (!o.value.empty() && o.value.back() == '\\') fail("a value may not end in '\\' (a .prm line continuation)");
  return o;
}

void apply_overrides(dealii::ParameterHandler &prm, const std::vector<ParameterOverride> &overrides,
                     const std::string &scope, const bool skip_undefined)
{
  std::optional<Tree> tree;
  for (const auto &o : overrides)
    {
      if (o.scope != scope) continue;
      if (!tree) tree = declared_tree(prm);
      const Resolved r = resolve(*tree, o.path);
      if (r.entry.empty())
        {
          if (skip_undefined) continue;
          throw InputError("--set", "'" + base::printable_excerpt(o.text(), 200) + "': there is no entry or subsection '" +
                                      base::printable_excerpt(r.missing, 80) + "' " +
                                      (r.deepest.empty() ? std::string("at the top level")
                                                         : "in subsection '" + r.deepest + "'") +
                                      hint_text(nearest_in(*tree, r.deepest, r.missing)));
        }
      std::string text;
      for (const auto &s : r.subsections) text += "subsection " + s + "\n";
      text += "set " + r.entry + " = " + o.value + "\n";
      for (std::size_t i = 0; i < r.subsections.size(); ++i) text += "end\n";
      try
        {
          prm.parse_input_from_string(text, "--set", skip_undefined);
        }
      catch (const dealii::ExceptionBase &e)
        {
          const std::string message = base::parse_error_text(e), explained = explained_pattern_mismatch(message);
          throw InputError("--set", "'" + base::printable_excerpt(o.text(), 200) + "': " +
                                      base::printable_excerpt(explained.empty() ? message : explained, 400));
        }
    }
}

void make_file_entries_absolute(dealii::ParameterHandler &prm, const std::string &directory)
{
  const std::function<void(const Tree &)> visit = [&](const Tree &node) {
    for (const auto &[key, child] : node)
      if (child.data() == "file entry")
        {
          const std::string value = base::trim(prm.get(key));
          if (!value.empty() && !std::filesystem::path(value).is_absolute())
            prm.set(key, (std::filesystem::absolute(std::filesystem::path(directory) / value)).lexically_normal().string());
        }
      else if (!is_entry(child))
        {
          prm.enter_subsection(key);
          visit(child);
          prm.leave_subsection();
        }
  };
  visit(declared_tree(prm));
}

std::vector<std::string> override_texts(const std::vector<ParameterOverride> &overrides)
{
  std::vector<std::string> texts;
  for (const auto &o : overrides) texts.push_back(o.text());
  return texts;
}

std::string nearest_declared_hint(const dealii::ParameterHandler &prm, const std::string &path, const std::string &name)
{
  return hint_text(nearest_in(declared_tree(prm), path, name));
}
} // namespace flextrack::io
