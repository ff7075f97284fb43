#include <fem/material.h>
#include <base/input_error.h>
#include <geometry/curve_library.h>

#include <sstream>

namespace flextrack::fem
{
using dealii::Patterns::Double;

namespace
{
// Physically meaningful ranges. The upper bounds are about ten times the stiffest (diamond,
// 1.2e12 Pa) and four times the densest (osmium, 22590 kg/m^3) solid, the lower ones below the
// softest (gels, 1e2 Pa) and lightest (aerogels, 1 kg/m^3): beyond them a value is a unit
// mistake, and 1e300 or 1e-300 would overflow or underflow the matrices (ARPACK then fails,
// exit 3, naming no entry).
const geometry::NumberRange modulus_range{0, 1e13, false, "Pa", 1};
const geometry::NumberRange density_range{0, 1e5, false, "kg/m^3", 1e-3};
} // namespace

void Material::declare_parameters(dealii::ParameterHandler &prm)
{
  prm.enter_subsection("Material");
  prm.declare_entry("Young's modulus", "2.1e11", Double(), "Young's modulus E [Pa], 1 to 1e13.");
  prm.declare_entry("Poisson's ratio", "0.3", Double(), "Poisson's ratio nu [-], -1 < nu < 0.5.");
  prm.declare_entry("Shear modulus", "0", Double(),
                    "Shear modulus G [Pa], 1 to 1e13; 0 means G = E / (2 (1 + nu)).");
  prm.declare_entry("Density", "7850", Double(), "Mass density rho [kg/m^3], 1e-3 to 1e5.");
  prm.leave_subsection();
}

Material Material::parse_parameters(dealii::ParameterHandler &prm, const std::string &section)
{
  const std::string path = section + "/Material/";
  prm.enter_subsection("Material");
  Material m;
  m.youngs_modulus = geometry::get_number(prm, "Young's modulus", path, modulus_range);
  m.density = geometry::get_number(prm, "Density", path, density_range);
  m.poisson_ratio = prm.get_double("Poisson's ratio");
  m.shear_modulus = prm.get_double("Shear modulus");
  prm.leave_subsection();
  if (!(m.poisson_ratio > -1 && m.poisson_ratio < 0.5))
    {
      std::ostringstream msg;
      msg << "must be > -1 and < 0.5 (got " << m.poisson_ratio << ")";
      throw InputError(path + "Poisson's ratio", msg.str());
    }
  if (m.shear_modulus == 0)
    m.shear_modulus = m.youngs_modulus / (2 * (1 + m.poisson_ratio));
  else if (!(m.shear_modulus > 0 && m.shear_modulus >= modulus_range.smallest && m.shear_modulus <= modulus_range.upper))
    {
      std::ostringstream msg;
      msg << "must be " << modulus_range.text(m.shear_modulus) << ", or 0 for E / (2 (1 + nu)) (got "
          << m.shear_modulus << ")";
      throw InputError(path + "Shear modulus", msg.str());
    }
  return m;
}
} // namespace flextrack::fem
