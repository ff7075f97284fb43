#include <base/parse_error.h>
#include <base/text.h>
#include <geometry/curve_library.h>
#include <geometry/section_frame.h>
#include <reduction/arm_geometry.h>

#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flextrack::reduction
{
namespace
{
void declare_arm_geometry(dealii::ParameterHandler &prm)
{
  prm.enter_subsection("Curve");
  geometry::declare_curve_parameters(prm);
  prm.leave_subsection();
  geometry::SectionFrame::declare_parameters(prm);
}

/// Refuses what would let the text reach outside itself or that FlexTrack never writes: deal.II
/// opens the file of an "include" line, and a '\' at a line's end joins lines (so "inc\" and
/// "lude FILE" would make one); control characters other than line ends and tabs.
void check_text(const std::string &text)
{
  if (text.size() > max_geometry_parameters_bytes)
    throw std::runtime_error("its 'geometry_parameters' text has " + std::to_string(text.size()) +
                             " bytes; at most " + std::to_string(max_geometry_parameters_bytes >> 20) +
                             " MiB are allowed");
  for (const char c : text)
    if (c == '\\' || (static_cast<unsigned char>(c) < 32 && c != '\n' && c != '\r' && c != '\t'))
      throw std::runtime_error("its 'geometry_parameters' text holds the character code " +
                               std::to_string(static_cast<unsigned char>(c)) +
                               "; a curve and section frame written by FlexTrack never do");
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (base::trim(line).rfind("include", 0) == 0)
      throw std::runtime_error("its 'geometry_parameters' text includes another file ('" +
                               base::printable_excerpt(base::trim(line), 60) + "'); it must be self-contained");
}
} // namespace

ArmGeometry parse_arm_geometry(const std::string &text)
{
  check_text(text);
  dealii::ParameterHandler prm;
  declare_arm_geometry(prm);
  const std::string what = "its 'geometry_parameters' text ";
  try
    {
      prm.parse_input_from_string(text, "", false);
    }
  catch (const dealii::ExceptionBase &e)
    {
      std::string message = base::printable_excerpt(base::parse_error_text(e), 400);
      // "Line <2> of the scene" (or deal.II's unclosed "of file <input string"): the text, here.
      for (const std::string noise : {"of the scene", "of file <input string>", "of file <input string"})
        if (const auto at = message.find(noise); at != std::string::npos) message.replace(at, noise.size(), "of the text");
      throw std::runtime_error(what + "is not a curve and section frame: " + message);
    }
  ArmGeometry g;
  try
    {
      prm.enter_subsection("Curve");
      prm.enter_subsection("Spline");
      const bool names_file = !base::trim(prm.get("Points file")).empty();
      prm.leave_subsection();
      if (names_file)
        throw std::runtime_error(what + "names a points file ('Curve/Spline/Points file'); the points must be inline");
      g.curve = geometry::parse_curve(prm, {"Curve", ""});
      prm.leave_subsection();
      g.frame = std::make_shared<geometry::SectionFrame>(geometry::SectionFrame::parse_parameters(prm, g.curve, {"", ""}));
    }
  catch (const dealii::ExceptionBase &e)
    {
      throw std::runtime_error(what + "does not describe a curve: " + base::printable_excerpt(base::parse_error_text(e), 400));
    }
  catch (const std::runtime_error &e) // InputError, CurveError, FrameError, ours
    {
      const std::string message = e.what();
      throw std::runtime_error(message.rfind(what, 0) == 0 ? message : what + "does not rebuild: " + message);
    }
  return g;
}

double arm_geometry_tolerance(const ArmModeData &arm)
{
  double largest = 0;
  for (const double x : arm.positions) largest = std::max(largest, std::abs(x));
  return 1e-9 * std::abs(arm.cell_s.back()) + 1e-12 * largest;
}

void check_arm_geometry(const geometry::Curve &curve, const ArmModeData &arm)
{
  const double tolerance = arm_geometry_tolerance(arm), L = curve.length();
  std::ostringstream m;
  m.precision(12);
  if (!(std::abs(L - arm.cell_s.back()) <= tolerance))
    {
      m << "the curve rebuilt from 'geometry_parameters' (" << curve.description() << ") is L = " << L
        << " m long, the arm's cells end at " << arm.cell_s.back() << " m (allowed difference " << tolerance
        << " m): the geometry text does not belong to this arm";
      throw std::runtime_error(m.str());
    }
  const unsigned int per_cell = arm.xi.size();
  double worst = 0, worst_s = 0;
  for (unsigned int c = 0; c < arm.n_cells(); ++c)
    for (unsigned int j = 0; j < per_cell; ++j)
      {
        const double s = std::clamp(arm.cell_s[c] + arm.xi[j] * (arm.cell_s[c + 1] - arm.cell_s[c]), 0.0, L);
        const auto x = curve.position(s);
        const double *stored = &arm.positions[3 * (c * per_cell + j)];
        const double d = std::hypot(x[0] - stored[0], x[1] - stored[1], x[2] - stored[2]);
        if (!(d <= worst)) worst = d, worst_s = s; // a NaN is kept as the worst
      }
  if (!(worst <= tolerance))
    {
      m << "the curve rebuilt from 'geometry_parameters' (" << curve.description() << ") is " << worst
        << " m away from the stored node position at s = " << worst_s << " m (allowed " << tolerance
        << " m): the geometry text does not belong to this arm";
      throw std::runtime_error(m.str());
    }
}

namespace
{
/// The curve and frame of @p text, built once per process (geometry/built_geometry.h): the body
/// scene's arms, built just before, usually have the same text.
ArmGeometry parsed_once(const std::string &text)
{
  if (const auto known = geometry::built_geometry(text)) return *known;
  ArmGeometry g = parse_arm_geometry(text); // throws for a text that does not rebuild: nothing kept
  geometry::remember_built_geometry(text, g);
  return g;
}
} // namespace

void rebuild_arm_geometry(ArmModeData &arm)
{
  auto g = parsed_once(arm.geometry_parameters);
  check_arm_geometry(*g.curve, arm);
  arm.curve = std::move(g.curve);
  arm.frame = std::move(g.frame);
}

void require_arm_geometry(const ArmModeData &arm)
{
  if (!arm.curve || !arm.frame)
    throw std::runtime_error("arm '" + arm.name +
                             "' of the reduced body has no stored curve and section frame (an arm built in code, "
                             "not read from a parameter file), so nothing can slide on it");
}
} // namespace flextrack::reduction
