// The curve kinds a parameter file can choose in "subsection Curve", each registered with its
// name, documentation, its own parameters and a factory (the ASPECT plugin pattern).
#pragma once

#include <geometry/curve.h>

#include <deal.II/base/parameter_handler.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::geometry
{
/// Where an entry is read from: its subsection path (for messages) and the directory that
/// relative file names are taken from.
struct ParseContext
{
  std::string section;   ///< e.g. "Arm/Curve"
  std::string directory; ///< the parameter file's directory
};

/// The allowed values of a numeric entry: lower < v (or lower <= v when @p lower_included),
/// smallest <= v and v <= upper, in @p unit ("m", "Pa", "-", ...). Every numeric entry of a
/// scene is checked against one when it is read: deal.II's Patterns::Double refuses nan and inf
/// in a file, but not 1e300, and a bound of 0 cannot say "> 0". @p smallest is the floor of a
/// positive quantity (1e-300 Pa underflows the matrices); a non-positive value is reported
/// against @p lower ("must be > 0 Pa"), a tiny positive one against @p smallest.
struct NumberRange
{
  double lower;
  double upper;
  bool lower_included;
  std::string unit;
  double smallest = -std::numeric_limits<double>::max();
  /// "> 0 m and <= 1e+06 m" (or ">= 1e-06 m and <= 1e+06 m" for a value above @p lower).
  std::string text(double value = std::numeric_limits<double>::quiet_NaN()) const;
};

/// @p value if it is finite and within @p range; otherwise InputError naming @p entry, the unit
/// and the range, e.g. "must be > 0 m and <= 1e+06 m (got -1)".
double checked_number(double value, const std::string &entry, const NumberRange &range);
/// The number in entry @p name of the current subsection, checked; @p path is the subsection
/// path for the message ("Arm/Curve/Arc/").
double get_number(dealii::ParameterHandler &prm, const std::string &name, const std::string &path,
                  const NumberRange &range);

struct CurveKind
{
  std::string name;
  std::string documentation;
  void (*declare)(dealii::ParameterHandler &prm);
  std::shared_ptr<const Curve> (*create)(dealii::ParameterHandler &prm, const ParseContext &where);
};

const std::vector<CurveKind> &curve_kinds();

/// Declare "Kind" and one subsection per kind in the current subsection.
void declare_curve_parameters(dealii::ParameterHandler &prm);
/// Build the selected curve; throws InputError naming the entry on bad values.
std::shared_ptr<const Curve> parse_curve(dealii::ParameterHandler &prm, const ParseContext &where);
} // namespace flextrack::geometry
