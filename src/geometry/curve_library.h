// The curve kinds a parameter file can choose in "subsection Curve", each registered with its
// name, documentation, its own parameters and a factory (the ASPECT plugin pattern).
#pragma once

#include <geometry/curve.h>

#include <deal.II/base/parameter_handler.h>

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
