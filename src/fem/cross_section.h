// Section properties of a beam. Axes: 1 = tangent, y = section frame's d2, z = tangent x y.
#pragma once

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <string>
#include <vector>

namespace flextrack::fem
{
struct CrossSection
{
  std::string shape = "explicit";
  double area = 0;             ///< A [m^2]
  double inertia_y = 0;        ///< Iy = int z^2 dA [m^4] (bending about y)
  double inertia_z = 0;        ///< Iz = int y^2 dA [m^4] (bending about z)
  double torsion_constant = 0; ///< Saint-Venant J [m^4]
  double polar_inertia = 0;    ///< Ip = Iy + Iz [m^4], for the rotary inertia about the tangent
  double shear_factor_y = 0;   ///< k_y [-] (shear along y)
  double shear_factor_z = 0;   ///< k_z [-]
  double size = 0;             ///< a characteristic dimension [m] (depth), for reports

  /// Cowper (1966) shear factors, Saint-Venant torsion constants: see the .cc file.
  static CrossSection circle(double diameter, double nu);
  static CrossSection tube(double outer_diameter, double inner_diameter, double nu);
  static CrossSection rectangle(double width_y, double height_z, double nu);
  /// Saint-Venant torsion constant of a solid rectangle (Timoshenko & Goodier, Theory of
  /// Elasticity, 3rd ed., sec. 109): J = a b^3 [1/3 - 64 b / (pi^5 a) sum tanh(n pi a / 2b) / n^5].
  static double rectangle_torsion_constant(double width, double height);

  /// The section's outline for drawing, as (y, z) corners [m] counter-clockwise in the section
  /// axes: a 16-gon of the outer diameter (circle, tube); the rectangle of equal area and second
  /// moments, w = sqrt(12 Iz / A), h = sqrt(12 Iy / A) (rectangle: its own; explicit: the
  /// equivalent rectangle, as a picture of its size and aspect).
  std::vector<std::array<double, 2>> outline() const;

  static void declare_parameters(dealii::ParameterHandler &prm);
  static CrossSection parse_parameters(dealii::ParameterHandler &prm, const std::string &section, double nu);
};
} // namespace flextrack::fem
