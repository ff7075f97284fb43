#include <fem/cross_section.h>
#include <base/input_error.h>
#include <base/text.h>
#include <geometry/curve_library.h>

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

std::vector<std::array<double, 2>> CrossSection::outline() const
{
  std::vector<std::array<double, 2>> corners;
  if (shape == "circle" || shape == "tube")
    {
      constexpr unsigned int sides = 16; // round enough for a picture, 16 points per ring of a tube
      for (unsigned int k = 0; k < sides; ++k)
        corners.push_back({{0.5 * size * std::cos(2 * M_PI * k / sides), 0.5 * size * std::sin(2 * M_PI * k / sides)}});
      return corners;
    }
  const double w = area > 0 ? std::sqrt(12 * inertia_z / area) : 0, h = area > 0 ? std::sqrt(12 * inertia_y / area) : 0;
  for (const auto &[y, z] : {std::array<double, 2>{{0.5, -0.5}}, {{0.5, 0.5}}, {{-0.5, 0.5}}, {{-0.5, -0.5}}})
    corners.push_back({{y * w, z * h}});
  return corners;
}

namespace
{
// Ranges of the section entries. The bounds are sanity limits, far beyond any beam section (from
// 1 micrometre to 100 m wide), so that a unit mistake, 1e300 or 1e-300 is refused by name
// instead of overflowing or underflowing the stiffness matrix (ARPACK then fails, exit 3).
const geometry::NumberRange dimension_range{0, 100, false, "m", 1e-6};
const geometry::NumberRange area_range{0, 1e4, false, "m^2", 1e-12};
const geometry::NumberRange moment_range{0, 1e8, false, "m^4", 1e-24};
const geometry::NumberRange shear_factor_range{0, 1, false, "-", 1e-3};

/// 'auto' (then @p automatic) or a number within @p range.
double number_or_auto(dealii::ParameterHandler &prm, const std::string &name, const std::string &path,
                      const geometry::NumberRange &range, const double automatic, const std::string &meaning)
{
  const std::string text = base::trim(prm.get(name));
  if (text == "auto") return automatic;
  const double v = base::parse_number(text, path + name, "'auto' or a number [" + range.unit + "]");
  if (!(v > range.lower && v >= range.smallest && v <= range.upper))
    {
      std::ostringstream m;
      m << "must be 'auto' (" << meaning << ") or " << range.text(v) << " (got " << v << ")";
      throw InputError(path + name, m.str());
    }
  return v;
}
} // namespace

void CrossSection::declare_parameters(dealii::ParameterHandler &prm)
{
  prm.enter_subsection("Cross section");
  prm.declare_entry("Shape", "circle", dealii::Patterns::Selection("circle|tube|rectangle|explicit"),
                    "Section shape: 'circle' (Diameter), 'tube' (Outer and Inner diameter), 'rectangle' "
                    "(Width along the section y axis, Height along z), 'explicit' (A, Iy, Iz, J, shear factors).");
  prm.declare_entry("Diameter", "0.02", Double(), "Circle diameter [m], 1e-6 to 100.");
  prm.declare_entry("Outer diameter", "0.03", Double(), "Tube outer diameter [m], > inner diameter, 1e-6 to 100.");
  prm.declare_entry("Inner diameter", "0.02", Double(), "Tube inner diameter [m], >= 0 and < outer diameter.");
  prm.declare_entry("Width", "0.02", Double(), "Rectangle width along the section y axis [m], 1e-6 to 100.");
  prm.declare_entry("Height", "0.02", Double(), "Rectangle height along the section z axis [m], 1e-6 to 100.");
  prm.declare_entry("Area", "0", Double(), "Explicit: area A [m^2], 1e-12 to 1e4.");
  prm.declare_entry("Iy", "0", Double(), "Explicit: second moment about the section y axis [m^4], 1e-24 to 1e8.");
  prm.declare_entry("Iz", "0", Double(), "Explicit: second moment about the section z axis [m^4], 1e-24 to 1e8.");
  prm.declare_entry("Torsion constant", "0", Double(),
                    "Explicit: Saint-Venant torsion constant J [m^4], 1e-24 to 1e8.");
  prm.declare_entry("Polar moment", "auto", dealii::Patterns::Anything(),
                    "Explicit: polar moment Ip for rotary inertia about the tangent [m^4], 1e-24 to 1e8; "
                    "'auto' means Iy + Iz.");
  prm.declare_entry("Shear factor y", "auto", dealii::Patterns::Anything(),
                    "Shear correction factor k = A_shear / A for shear along y [-], 0.001 to 1; 'auto' means "
                    "Cowper's value for the shape (explicit: 5/6).");
  prm.declare_entry("Shear factor z", "auto", dealii::Patterns::Anything(),
                    "As 'Shear factor y', for shear along z [-].");
  prm.leave_subsection();
}

CrossSection CrossSection::parse_parameters(dealii::ParameterHandler &prm, const std::string &section,
                                            const double nu)
{
  // An InputError ends the run, so the subsection need not be left on the way out.
  const std::string path = section + "/Cross section/";
  prm.enter_subsection("Cross section");
  auto get = [&](const std::string &name, const geometry::NumberRange &range) {
    return geometry::get_number(prm, name, path, range);
  };
  const std::string shape = prm.get("Shape");
  CrossSection s;
  if (shape == "circle")
    s = circle(get("Diameter", dimension_range), nu);
  else if (shape == "tube")
    {
      const double D = get("Outer diameter", dimension_range);
      const double d = get("Inner diameter", {0, 100, true, "m"}); // 0: a solid circle
      if (!(d < D))
        {
          std::ostringstream m;
          m << "must be smaller than the outer diameter " << D << " m (got " << d << " m)";
          throw InputError(path + "Inner diameter", m.str());
        }
      s = tube(D, d, nu);
    }
  else if (shape == "rectangle")
    s = rectangle(get("Width", dimension_range), get("Height", dimension_range), nu);
  else
    {
      s.shape = "explicit";
      s.area = get("Area", area_range);
      s.inertia_y = get("Iy", moment_range);
      s.inertia_z = get("Iz", moment_range);
      s.torsion_constant = get("Torsion constant", moment_range);
      s.polar_inertia = number_or_auto(prm, "Polar moment", path, moment_range, s.inertia_y + s.inertia_z, "Iy + Iz");
      s.shear_factor_y = s.shear_factor_z = 5.0 / 6.0;
      s.size = std::sqrt(12 * std::max(s.inertia_y, s.inertia_z) / s.area);
    }
  s.shear_factor_y = number_or_auto(prm, "Shear factor y", path, shear_factor_range, s.shear_factor_y, "Cowper's value");
  s.shear_factor_z = number_or_auto(prm, "Shear factor z", path, shear_factor_range, s.shear_factor_z, "Cowper's value");
  prm.leave_subsection();
  return s;
}
} // namespace flextrack::fem
