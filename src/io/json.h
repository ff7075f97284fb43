// A minimal JSON object writer for result summaries (keys keep their insertion order).
#pragma once

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace flextrack::io
{
class JsonObject
{
public:
  JsonObject &add(const std::string &key, const std::string &text) { return raw(key, quote(text)); }
  JsonObject &add(const std::string &key, const char *text) { return raw(key, quote(text)); }
  JsonObject &add(const std::string &key, double value) { return raw(key, number(value)); }
  JsonObject &add(const std::string &key, int value) { return raw(key, std::to_string(value)); }
  JsonObject &add(const std::string &key, unsigned int value) { return raw(key, std::to_string(value)); }
  JsonObject &add(const std::string &key, const std::vector<double> &values)
  {
    std::string s = "[";
    for (std::size_t i = 0; i < values.size(); ++i) s += (i ? ", " : "") + number(values[i]);
    return raw(key, s + "]");
  }
  JsonObject &add(const std::string &key, const std::vector<std::string> &texts)
  {
    std::string s = "[";
    for (std::size_t i = 0; i < texts.size(); ++i) s += (i ? ", " : "") + quote(texts[i]);
    return raw(key, s + "]");
  }
  JsonObject &add(const std::string &key, const JsonObject &object) { return raw(key, object.str()); }
  /// @p json must already be valid JSON text.
  JsonObject &raw(const std::string &key, const std::string &json)
  {
    members.emplace_back(key, json);
    return *this;
  }
  std::string str(int indent = 0) const
  {
    const std::string pad(indent + 2, ' ');
    std::string s = "{\n";
    for (std::size_t i = 0; i < members.size(); ++i)
      s += pad + quote(members[i].first) + ": " + members[i].second + (i + 1 < members.size() ? ",\n" : "\n");
    return s + std::string(indent, ' ') + "}";
  }
  static std::string quote(const std::string &text)
  {
    std::string s = "\"";
    for (const char c : text)
      switch (c)
        {
          case '"': s += "\\\""; break;
          case '\\': s += "\\\\"; break;
          case '\n': s += "\\n"; break;
          case '\t': s += "\\t"; break;
          default:
            if (static_cast<unsigned char>(c) < 0x20)
              {
                // Other control characters are not allowed raw in a JSON string.
                char code[8];
                std::snprintf(code, sizeof code, "\\u%04x", static_cast<unsigned int>(c));
                s += code;
              }
            else
              s += c;
        }
    return s + "\"";
  }
  static std::string number(double v)
  {
    if (!std::isfinite(v)) return "null";
    std::ostringstream o;
    o.precision(17);
    o << v;
    return o.str();
  }

private:
  std::vector<std::pair<std::string, std::string>> members;
};
} // namespace flextrack::io
