#include <geometry/built_geometry.h>

#include <map>
#include <mutex>

namespace flextrack::geometry
{
namespace
{
std::mutex mutex;
std::map<std::string, CurveAndFrame> &known()
{
  static std::map<std::string, CurveAndFrame> map;
  return map;
}
} // namespace

std::optional<CurveAndFrame> built_geometry(const std::string &text)
{
  std::lock_guard<std::mutex> lock(mutex);
  if (const auto found = known().find(text); found != known().end()) return found->second;
  return std::nullopt;
}

void remember_built_geometry(const std::string &text, const CurveAndFrame &geometry)
{
  std::lock_guard<std::mutex> lock(mutex);
  if (known().size() >= 64) known().clear(); // a bound, for a long study of many geometries
  known().emplace(text, geometry);
}
} // namespace flextrack::geometry
