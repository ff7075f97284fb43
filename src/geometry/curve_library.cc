#include <base/text.h>
#include <geometry/curve_library.h>
#include <geometry/expression.h>
#include <geometry/spline.h>
#include <base/input_error.h>

#include <cmath>
#include <sstream>

namespace flextrack::geometry
{
using dealii::ParameterHandler;
using dealii::Patterns::Anything;
using dealii::Patterns::Double;
using dealii::Patterns::List;

namespace
{
Vec3 read_vector(ParameterHandler &prm, const std::string &entry)
{
  const auto v = base::parse_vector3(prm.get(entry), entry, "m");
  return Vec3({v[0], v[1], v[2]});
}

const auto three_numbers = List(Double(), 3, 3, ",");

std::shared_ptr<const Curve> checked(std::shared_ptr<const Curve> curve, const ParseContext &where)
{
  // A curve of zero length cannot carry an arm; say so instead of dividing by zero later.
  const double scale = std::max(1.0, curve->position(0).norm());
  if (!(curve->length() > 1e-12 * scale))
    throw InputError(where.section, "the curve (" + curve->description() + ") has zero length; "
                     "give points, radius, pitch or expressions that describe a curve of positive length");
  return curve;
}

// ---- line ---------------------------------------------------------------------------------
void declare_line(ParameterHandler &prm)
{
  prm.enter_subsection("Line");
  prm.declare_entry("Start point", "0, 0, 0", three_numbers, "Start of the line: x, y, z [m].");
  prm.declare_entry("End point", "1, 0, 0", three_numbers, "End of the line: x, y, z [m].");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_line(ParameterHandler &prm, const ParseContext &where)
{
  prm.enter_subsection("Line");
  const Vec3 a = read_vector(prm, "Start point"), b = read_vector(prm, "End point");
  prm.leave_subsection();
  const double L = (b - a).norm();
  const Vec3 e = L > 0 ? (b - a) / L : Vec3();
  auto y = [a, e](const Jet &s) {
    Jet3 r;
    for (int d = 0; d < 3; ++d) r[d] = Jet::constant(a[d]) + e[d] * s;
    return r;
  };
  if (!(L > 0))
    throw InputError(where.section + "/Line", "start and end point coincide: the curve has zero length; "
                     "give two distinct points [m]");
  return checked(std::make_shared<Curve>("line", y, 0.0, L, true), where);
}

// ---- arc ----------------------------------------------------------------------------------
void declare_arc(ParameterHandler &prm)
{
  prm.enter_subsection("Arc");
  prm.declare_entry("Radius", "1", Double(), "Radius of the circular arc [m], > 0.");
  prm.declare_entry("Angle", "1.5707963267948966", Double(),
                    "Angle swept by the arc [rad], > 0; 6.283185307179586 (2 pi) makes a closed ring.");
  prm.declare_entry("Centre", "0, 0, 0", three_numbers, "Centre of the circle: x, y, z [m]. The arc lies in "
                    "the plane z = const, starts at centre + (R, 0, 0) and turns counter-clockwise about +z.");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_arc(ParameterHandler &prm, const ParseContext &where)
{
  prm.enter_subsection("Arc");
  const double R = prm.get_double("Radius"), angle = prm.get_double("Angle");
  const Vec3 c = read_vector(prm, "Centre");
  prm.leave_subsection();
  if (!(R > 0))
    throw InputError(where.section + "/Arc/Radius", "must be > 0 m (got " + std::to_string(R) + ")");
  if (!(angle > 0) || angle > 2 * M_PI * (1 + 1e-12))
    throw InputError(where.section + "/Arc/Angle", "must satisfy 0 < angle <= 2 pi rad (got " + std::to_string(angle) + ")");
  // A full turn typed with limited digits is still a ring: snap it to 2 pi exactly.
  const double sweep = std::abs(angle - 2 * M_PI) < 1e-9 ? 2 * M_PI : angle;
  auto y = [R, c](const Jet &s) {
    Jet sn, cs;
    sin_cos((1.0 / R) * s, sn, cs);
    return Jet3{Jet::constant(c[0]) + R * cs, Jet::constant(c[1]) + R * sn, Jet::constant(c[2])};
  };
  return checked(std::make_shared<Curve>("circular arc", y, 0.0, R * sweep, true), where);
}

// ---- helix --------------------------------------------------------------------------------
void declare_helix(ParameterHandler &prm)
{
  prm.enter_subsection("Helix");
  prm.declare_entry("Radius", "0.5", Double(), "Helix radius a [m], >= 0.");
  prm.declare_entry("Pitch", "0.4", Double(), "Rise per turn h [m]; the helix is "
                    "(a cos t, a sin t, h t / (2 pi)) about the z axis.");
  prm.declare_entry("Turns", "1.5", Double(), "Number of turns [-], > 0.");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_helix(ParameterHandler &prm, const ParseContext &where)
{
  prm.enter_subsection("Helix");
  const double a = prm.get_double("Radius"), h = prm.get_double("Pitch"), turns = prm.get_double("Turns");
  prm.leave_subsection();
  if (a < 0)
    throw InputError(where.section + "/Helix/Radius", "must be >= 0 m (got " + std::to_string(a) + ")");
  if (!(turns > 0))
    throw InputError(where.section + "/Helix/Turns", "must be > 0 (got " + std::to_string(turns) + ")");
  const double c = h / (2 * M_PI), w = std::sqrt(a * a + c * c);
  if (!(w > 0))
    throw InputError(where.section + "/Helix", "radius and pitch are both zero: the curve has zero length; "
                     "give Radius > 0 m or Pitch != 0 m");
  // Exact arc-length form: t = s / sqrt(a^2 + c^2).
  auto y = [a, c, w](const Jet &s) {
    Jet sn, cs;
    sin_cos((1.0 / w) * s, sn, cs);
    return Jet3{a * cs, a * sn, (c / w) * s};
  };
  return checked(std::make_shared<Curve>("helix", y, 0.0, 2 * M_PI * turns * w, true), where);
}

// ---- expressions (type I in t, type II in s) ------------------------------------------------
void declare_expressions(ParameterHandler &prm, const std::string &variable)
{
  for (const char *axis : {"x", "y", "z"})
    prm.declare_entry(std::string(axis) + "(" + variable + ")", "0", Anything(),
                      std::string("Coordinate ") + axis + " [m] as an expression in " + variable +
                        ": + - * / ^, sin cos tan exp log sqrt sinh cosh tanh atan abs, pi and the Constants.");
  prm.declare_entry("Constants", "", Anything(),
                    "Named constants usable in the expressions, e.g. \"a=0.5, c=0.1\" (SI units).");
}

std::shared_ptr<const Curve> create_from_expressions(ParameterHandler &prm, const ParseContext &where,
                                                     const std::string &subsection, const std::string &variable,
                                                     double begin, double end, bool arc_length)
{
  const std::string path = where.section + "/" + subsection;
  std::map<std::string, double> constants;
  try
    {
      constants = parse_constants(prm.get("Constants"));
    }
  catch (const ExpressionError &e)
    {
      throw InputError(path + "/Constants", e.what());
    }
  std::vector<Expression> xyz;
  for (const char *axis : {"x", "y", "z"})
    {
      const std::string entry = std::string(axis) + "(" + variable + ")";
      try
        {
          xyz.emplace_back(prm.get(entry), variable, constants);
        }
      catch (const ExpressionError &e)
        {
          throw InputError(path + "/" + entry, e.what());
        }
    }
  auto y = [xyz](const Jet &p) {
    Jet3 r;
    for (int d = 0; d < 3; ++d) r[d] = xyz[d].jet(p.c[0]);
    // jet(p) is a jet in p itself; compose with the incoming jet for general arguments.
    for (int d = 0; d < 3; ++d) r[d] = compose(r[d], p);
    return r;
  };
  // The expressions must be finite over the whole range.
  for (int i = 0; i <= 64; ++i)
    {
      const double p = begin + (end - begin) * i / 64;
      const Jet3 r = y(Jet::variable(p));
      for (int d = 0; d < 3; ++d)
        for (int k = 0; k <= 1; ++k)
          if (!std::isfinite(r[d].c[k]))
            throw InputError(path, "the expression for " + std::string(1, "xyz"[d]) + "(" + variable + ") or its "
                             "derivative is not finite at " + variable + " = " + std::to_string(p) +
                             "; the curve must be smooth over the whole range");
      if (arc_length && std::abs(Vec3({r[0].c[1], r[1].c[1], r[2].c[1]}).norm() - 1) > 1e-6)
        throw InputError(path, "the curve is not parametrised by arc length (|dy/ds| = " +
                         std::to_string(Vec3({r[0].c[1], r[1].c[1], r[2].c[1]}).norm()) + " at s = " +
                         std::to_string(p) + ", must be 1); use Kind = parametric for a general parameter");
    }
  return checked(std::make_shared<Curve>(std::string(arc_length ? "arc-length" : "parametric") + " curve (" +
                                           xyz[0].text() + ", " + xyz[1].text() + ", " + xyz[2].text() + ")",
                                         y, begin, end, arc_length),
                 where);
}

void declare_parametric(ParameterHandler &prm)
{
  prm.enter_subsection("Parametric");
  declare_expressions(prm, "t");
  prm.declare_entry("Parameter start", "0", Double(), "First value of the parameter t [-].");
  prm.declare_entry("Parameter end", "1", Double(), "Last value of the parameter t [-], > start.");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_parametric(ParameterHandler &prm, const ParseContext &where)
{
  prm.enter_subsection("Parametric");
  const double t0 = prm.get_double("Parameter start"), t1 = prm.get_double("Parameter end");
  if (!(t1 > t0))
    {
      prm.leave_subsection();
      throw InputError(where.section + "/Parametric/Parameter end", "must be greater than 'Parameter start'");
    }
  try
    {
      auto curve = create_from_expressions(prm, where, "Parametric", "t", t0, t1, false);
      prm.leave_subsection();
      return curve;
    }
  catch (...)
    {
      prm.leave_subsection();
      throw;
    }
}

void declare_arc_length(ParameterHandler &prm)
{
  prm.enter_subsection("Arc length");
  declare_expressions(prm, "s");
  prm.declare_entry("Length", "1", Double(), "Length L of the curve [m], > 0; s runs over [0, L].");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_arc_length(ParameterHandler &prm, const ParseContext &where)
{
  prm.enter_subsection("Arc length");
  const double L = prm.get_double("Length");
  try
    {
      if (!(L > 0))
        throw InputError(where.section + "/Arc length/Length", "must be > 0 m (got " + std::to_string(L) + ")");
      auto curve = create_from_expressions(prm, where, "Arc length", "s", 0.0, L, true);
      prm.leave_subsection();
      return curve;
    }
  catch (...)
    {
      prm.leave_subsection();
      throw;
    }
}

// ---- spline -------------------------------------------------------------------------------
void declare_spline(ParameterHandler &prm)
{
  prm.enter_subsection("Spline");
  prm.declare_entry("Points file", "", Anything(),
                    "Text file with one point \"x y z\" [m] per line (blanks or commas; # starts a "
                    "comment), relative to the parameter file's directory. A natural cubic spline in "
                    "chord length interpolates the points.");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_spline(ParameterHandler &prm, const ParseContext &where)
{
  prm.enter_subsection("Spline");
  std::string file = prm.get("Points file");
  prm.leave_subsection();
  if (!file.empty() && file[0] != '/' && !where.directory.empty())
    file = where.directory + "/" + file;
  return checked(make_spline_curve(file, where.section + "/Spline/Points file"), where);
}
} // namespace

const std::vector<CurveKind> &curve_kinds()
{
  static const std::vector<CurveKind> kinds = {
    {"line", "straight line between two points", declare_line, create_line},
    {"arc", "circular arc in a plane (2 pi: a closed ring)", declare_arc, create_arc},
    {"helix", "circular helix about the z axis", declare_helix, create_helix},
    {"parametric", "type I: x, y, z as expressions in a general parameter t", declare_parametric, create_parametric},
    {"arc length", "type II: x, y, z as expressions in the arc length s", declare_arc_length, create_arc_length},
    {"spline", "cubic spline through points read from a file", declare_spline, create_spline}};
  return kinds;
}

void declare_curve_parameters(ParameterHandler &prm)
{
  std::string names, doc = "Kind of centre-line curve:";
  for (const auto &k : curve_kinds())
    {
      names += (names.empty() ? "" : "|") + k.name;
      doc += " '" + k.name + "': " + k.documentation + ";";
    }
  prm.declare_entry("Kind", "helix", dealii::Patterns::Selection(names), doc);
  for (const auto &k : curve_kinds())
    k.declare(prm);
}

std::shared_ptr<const Curve> parse_curve(ParameterHandler &prm, const ParseContext &where)
{
  const std::string kind = prm.get("Kind");
  for (const auto &k : curve_kinds())
    if (k.name == kind)
      return k.create(prm, where);
  throw InputError(where.section + "/Kind", "unknown curve kind '" + kind + "'");
}
} // namespace flextrack::geometry
