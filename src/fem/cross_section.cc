#include <fem/cross_section.h>
#include <base/input_error.h>

#include <cmath>
#include <sstream>

namespace flextrack::fem
{
using dealii::Patterns::Double;

CrossSection CrossSection::circle(const double d, const double nu)
{
  CrossSection s;
  s.shape = "circle";
  s.area = M_PI * d * d / 4;
  s.inertia_y = s.inertia_z = M_PI * std::pow(d, 4) / 64;
  s.torsion_constant = s.polar_inertia = M_PI * std::pow(d, 4) / 32;
  // Cowper, J. Appl. Mech. 33 (1966) 335, solid circle.
  s.shear_factor_y = s.shear_factor_z = 6 * (1 + nu) / (7 + 6 * nu);
  s.size = d;
  return s;
}

CrossSection CrossSection::tube(const double D, const double d, const double nu)
{
  CrossSection s;
  s.shape = "tube";
  s.area = M_PI * (D * D - d * d) / 4;
  s.inertia_y = s.inertia_z = M_PI * (std::pow(D, 4) - std::pow(d, 4)) / 64;
  s.torsion_constant = s.polar_inertia = M_PI * (std::pow(D, 4) - std::pow(d, 4)) / 32;
  // Cowper (1966), hollow circle with m = d / D.
  const double m = d / D, q = (1 + m * m) * (1 + m * m);
  s.shear_factor_y = s.shear_factor_z = 6 * (1 + nu) * q / ((7 + 6 * nu) * q + (20 + 12 * nu) * m * m);
  s.size = D;
  return s;
}

double CrossSection::rectangle_torsion_constant(const double width, const double height)
{
  const double a = std::max(width, height), b = std::min(width, height);
  double sum = 0;
  for (int n = 1; n < 200; n += 2)
    sum += std::tanh(n * M_PI * a / (2 * b)) / std::pow(n, 5);
  return a * b * b * b * (1.0 / 3 - 64 * b / (std::pow(M_PI, 5) * a) * sum);
}

CrossSection CrossSection::rectangle(const double w, const double h, const double nu)
{
  CrossSection s;
  s.shape = "rectangle";
  s.area = w * h;
  s.inertia_y = w * h * h * h / 12;
  s.inertia_z = h * w * w * w / 12;
  s.polar_inertia = s.inertia_y + s.inertia_z;
  s.torsion_constant = rectangle_torsion_constant(w, h);
  // Cowper (1966), rectangle.
  s.shear_factor_y = s.shear_factor_z = 10 * (1 + nu) / (12 + 11 * nu);
  s.size = std::max(w, h);
  return s;
}

void CrossSection::declare_parameters(dealii::ParameterHandler &prm)
{
  prm.enter_subsection("Cross section");
  prm.declare_entry("Shape", "circle", dealii::Patterns::Selection("circle|tube|rectangle|explicit"),
                    "Section shape: 'circle' (Diameter), 'tube' (Outer and Inner diameter), 'rectangle' "
                    "(Width along the section y axis, Height along z), 'explicit' (A, Iy, Iz, J, shear factors).");
  prm.declare_entry("Diameter", "0.02", Double(), "Circle diameter [m], > 0.");
  prm.declare_entry("Outer diameter", "0.03", Double(), "Tube outer diameter [m], > inner diameter.");
  prm.declare_entry("Inner diameter", "0.02", Double(), "Tube inner diameter [m], >= 0.");
  prm.declare_entry("Width", "0.02", Double(), "Rectangle width along the section y axis [m], > 0.");
  prm.declare_entry("Height", "0.02", Double(), "Rectangle height along the section z axis [m], > 0.");
  prm.declare_entry("Area", "0", Double(), "Explicit: area A [m^2], > 0.");
  prm.declare_entry("Iy", "0", Double(), "Explicit: second moment about the section y axis [m^4], > 0.");
  prm.declare_entry("Iz", "0", Double(), "Explicit: second moment about the section z axis [m^4], > 0.");
  prm.declare_entry("Torsion constant", "0", Double(), "Explicit: Saint-Venant torsion constant J [m^4], > 0.");
  prm.declare_entry("Polar moment", "0", Double(),
                    "Explicit: polar moment Ip for rotary inertia about the tangent [m^4]; 0 means Iy + Iz.");
  prm.declare_entry("Shear factor y", "0", Double(),
                    "Shear correction factor for shear along y [-], > 0; 0 means Cowper's value for the "
                    "shape (explicit: 5/6).");
  prm.declare_entry("Shear factor z", "0", Double(), "As 'Shear factor y', for shear along z [-].");
  prm.leave_subsection();
}

CrossSection CrossSection::parse_parameters(dealii::ParameterHandler &prm, const std::string &section,
                                            const double nu)
{
  const std::string path = section + "/Cross section/";
  prm.enter_subsection("Cross section");
  auto positive = [&](const std::string &entry) {
    const double v = prm.get_double(entry);
    if (!(v > 0))
      {
        std::ostringstream m;
        m << "must be > 0 (got " << v << ")";
        prm.leave_subsection();
        throw InputError(path + entry, m.str());
      }
    return v;
  };
  const std::string shape = prm.get("Shape");
  CrossSection s;
  if (shape == "circle")
    s = circle(positive("Diameter"), nu);
  else if (shape == "tube")
    {
      const double D = positive("Outer diameter"), d = prm.get_double("Inner diameter");
      if (!(d >= 0 && d < D))
        {
          prm.leave_subsection();
          throw InputError(path + "Inner diameter", "must satisfy 0 <= inner < outer diameter [m]");
        }
      s = tube(D, d, nu);
    }
  else if (shape == "rectangle")
    s = rectangle(positive("Width"), positive("Height"), nu);
  else
    {
      s.shape = "explicit";
      s.area = positive("Area");
      s.inertia_y = positive("Iy");
      s.inertia_z = positive("Iz");
      s.torsion_constant = positive("Torsion constant");
      s.polar_inertia = prm.get_double("Polar moment") > 0 ? prm.get_double("Polar moment") : s.inertia_y + s.inertia_z;
      s.shear_factor_y = s.shear_factor_z = 5.0 / 6.0;
      s.size = std::sqrt(12 * std::max(s.inertia_y, s.inertia_z) / s.area);
    }
  if (prm.get_double("Shear factor y") > 0) s.shear_factor_y = prm.get_double("Shear factor y");
  if (prm.get_double("Shear factor z") > 0) s.shear_factor_z = prm.get_double("Shear factor z");
  prm.leave_subsection();
  return s;
}
} // namespace flextrack::fem
