// Isotropic linear elastic material (SI units).
#pragma once

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace flextrack::fem
{
struct Material
{
  double youngs_modulus = 2.1e11; ///< E [Pa]
  double poisson_ratio = 0.3;     ///< nu [-]
  double shear_modulus = 0;       ///< G [Pa]
  double density = 7850;          ///< rho [kg/m^3]

  static void declare_parameters(dealii::ParameterHandler &prm);
  /// Reads and checks the values; @p section names the subsection in error messages.
  static Material parse_parameters(dealii::ParameterHandler &prm, const std::string &section);
};
} // namespace flextrack::fem
