#include <fem/material.h>
#include <base/input_error.h>

#include <sstream>

namespace flextrack::fem
{
using dealii::Patterns::Double;

void Material::declare_parameters(dealii::ParameterHandler &prm)
{
  prm.enter_subsection("Material");
  prm.declare_entry("Young's modulus", "2.1e11", Double(), "Young's modulus E [Pa], > 0.");
  prm.declare_entry("Poisson's ratio", "0.3", Double(), "Poisson's ratio nu [-], -1 < nu < 0.5.");
  prm.declare_entry("Shear modulus", "0", Double(),
                    "Shear modulus G [Pa], > 0; 0 means G = E / (2 (1 + nu)).");
  prm.declare_entry("Density", "7850", Double(), "Mass density rho [kg/m^3], > 0.");
  prm.leave_subsection();
}

Material Material::parse_parameters(dealii::ParameterHandler &prm, const std::string &section)
{
  const std::string path = section + "/Material/";
  prm.enter_subsection("Material");
  Material m;
  m.youngs_modulus = prm.get_double("Young's modulus");
  m.poisson_ratio = prm.get_double("Poisson's ratio");
  m.shear_modulus = prm.get_double("Shear modulus");
  m.density = prm.get_double("Density");
  prm.leave_subsection();
  auto require = [&](bool ok, const std::string &entry, const std::string &allowed, double value) {
    if (!ok)
      {
        std::ostringstream msg;
        msg << "must be " << allowed << " (got " << value << ")";
        throw InputError(path + entry, msg.str());
      }
  };
  require(m.youngs_modulus > 0, "Young's modulus", "> 0 Pa", m.youngs_modulus);
  require(m.density > 0, "Density", "> 0 kg/m^3", m.density);
  require(m.poisson_ratio > -1 && m.poisson_ratio < 0.5, "Poisson's ratio", "in (-1, 0.5)", m.poisson_ratio);
  require(m.shear_modulus >= 0, "Shear modulus", "> 0 Pa, or 0 for E / (2 (1 + nu))", m.shear_modulus);
  if (m.shear_modulus == 0)
    m.shear_modulus = m.youngs_modulus / (2 * (1 + m.poisson_ratio));
  return m;
}
} // namespace flextrack::fem
