#include <base/text.h>
#include <geometry/curve_library.h>
#include <geometry/expression.h>
#include <geometry/spline.h>
#include <base/input_error.h>

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <cmath>
#include <sstream>
#include <vector>

namespace flextrack::geometry
{
using dealii::ParameterHandler;
using dealii::Patterns::Anything;
using dealii::Patterns::Double;
using dealii::Patterns::List;

namespace
{
/// Whole numbers below 1e7 in full (100000), others in 6 significant digits (1e+13).
std::string format(const double v)
{
  std::ostringstream m;
  if (v == std::floor(v) && std::abs(v) < 1e7)
    m << static_cast<long>(v);
  else
    m << v;
  return m.str();
}
} // namespace

std::string NumberRange::text(const double value) const
{
  const std::string u = unit == "-" || unit.empty() ? "" : " " + unit;
  const bool above_lower = lower_included ? value >= lower : value > lower;
  if (above_lower && smallest > lower)
    return ">= " + format(smallest) + u + " and <= " + format(upper) + u;
  return (lower_included ? ">= " : "> ") + format(lower) + u + " and <= " + format(upper) + u;
}

double checked_number(const double value, const std::string &entry, const NumberRange &range)
{
  const bool above = range.lower_included ? value >= range.lower : value > range.lower;
  if (!(std::isfinite(value) && above && value >= range.smallest && value <= range.upper))
    throw InputError(entry, "must be " + range.text(value) + " (got " + format(value) + ")");
  return value;
}

double get_number(ParameterHandler &prm, const std::string &name, const std::string &path, const NumberRange &range)
{
  const std::string entry = path + name;
  return checked_number(base::parse_number(prm.get(name), entry, "a number [" + range.unit + "]"), entry, range);
}

namespace
{
// Ranges of the curve entries; the upper bounds are sanity limits (see max_coordinate).
const NumberRange coordinate{-max_coordinate, max_coordinate, true, "m"};
const NumberRange positive_length{0, max_curve_length, false, "m", 1e-6};

Vec3 read_point(ParameterHandler &prm, const std::string &name, const std::string &path)
{
  const std::string entry = path + name;
  const auto v = base::parse_vector3(prm.get(name), entry, "m");
  for (const double c : v)
    if (!(std::abs(c) <= max_coordinate))
      {
        std::ostringstream m;
        m << "coordinate " << c << " m; allowed: coordinates of at most " << max_coordinate << " m in size";
        throw InputError(entry, m.str());
      }
  return Vec3({v[0], v[1], v[2]});
}

const auto three_numbers = List(Double(), 3, 3, ",");

/// Builds a Curve, turning a CurveError into an InputError naming @p entry.
template <typename... Args>
std::shared_ptr<const Curve> make_curve(const std::string &entry, Args &&...args)
{
  try
    {
      return std::make_shared<Curve>(std::forward<Args>(args)...);
    }
  catch (const CurveError &e)
    {
      throw InputError(entry, e.what());
    }
}

/// The entries that describe a curve, for messages: the kind's subsection, the entry of each
/// coordinate (the expressions; otherwise the subsection) and what to change if it has no length.
struct CurveEntries
{
  std::string section;
  std::array<std::string, 3> coordinate;
  std::string advice;
};

CurveEntries entries_of(const std::string &section, const std::string &advice)
{
  return {section, {{section, section, section}}, advice};
}

/// Smallest distance between the segments [a, b] and [c, d] [m] (clamped closest points).
double segment_distance(const Point<3> &a, const Point<3> &b, const Point<3> &c, const Point<3> &d)
{
  const Vec3 u = b - a, v = d - c, w = a - c;
  const double uu = u * u, uv = u * v, vv = v * v, uw = u * w, vw = v * w, det = uu * vv - uv * uv;
  double x = det > 1e-14 * uu * vv ? std::clamp((uv * vw - vv * uw) / det, 0.0, 1.0) : 0.0;
  double y = vv > 0 ? std::clamp((uv * x + vw) / vv, 0.0, 1.0) : 0.0;
  x = uu > 0 ? std::clamp((uv * y - uw) / uu, 0.0, 1.0) : 0.0;
  return (w + x * u - y * v).norm();
}

/// Refuses a curve that crosses or touches itself (it would put two parts of an arm in one
/// place). The polygon of the samples @p points (spaced @p h along the curve) lies within the
/// sagitta k h^2 / 8 of the curve; two segments that are not neighbours along the curve and come
/// closer than that (plus 1e-9 L of round-off) cross or touch. The ends of a closed ring may meet.
/// Candidate pairs come from a grid of cells of at least h: linear in the number of samples.
void refuse_self_crossing(const Curve &curve, const std::vector<Point<3>> &points, const double h, const double L,
                          const double scale, const std::string &what, const std::string &entry)
{
  const int samples = static_cast<int>(points.size()) - 1;
  double sagitta = 0;
  for (int i = 0; i < samples; ++i)
    {
      const double k = curve.geometry(L * (i + 0.5) / samples).curvature;
      if (std::isfinite(k)) sagitta = std::max(sagitta, k * h * h / 8);
    }
  const double touching = 2 * sagitta + 1e-9 * std::max(L, scale);
  // Each segment is entered in the cells its box (grown by `touching`) overlaps; pairs that share
  // a cell are measured. A cell is at least as large as a segment, so a segment meets at most 8.
  const double cell = std::max(h, touching) * 1.000001;
  Point<3> low = points[0];
  for (const auto &p : points)
    for (int d = 0; d < 3; ++d) low[d] = std::min(low[d], p[d]);
  std::unordered_map<std::uint64_t, std::vector<int>> grid;
  const auto cell_index = [&](const double x, const int d) { return static_cast<std::int64_t>(std::floor((x - low[d]) / cell)); };
  for (int i = 0; i < samples; ++i)
    {
      std::int64_t from[3], to[3];
      for (int d = 0; d < 3; ++d)
        {
          from[d] = cell_index(std::min(points[i][d], points[i + 1][d]) - touching, d);
          to[d] = cell_index(std::max(points[i][d], points[i + 1][d]) + touching, d);
        }
      for (auto a = from[0]; a <= to[0]; ++a)
        for (auto b = from[1]; b <= to[1]; ++b)
          for (auto e = from[2]; e <= to[2]; ++e)
            grid[(static_cast<std::uint64_t>(a + 1) * 2097152 + static_cast<std::uint64_t>(b + 1)) * 2097152 +
                 static_cast<std::uint64_t>(e + 1)]
              .push_back(i);
    }
  // The first crossing along the curve is reported (the grid's order is not the curve's).
  int first_i = samples, first_j = samples;
  double first_gap = 0;
  for (const auto &[key, members] : grid)
    for (std::size_t x = 0; x < members.size(); ++x)
      for (std::size_t y = x + 1; y < members.size(); ++y)
        {
          const int i = std::min(members[x], members[y]), j = std::max(members[x], members[y]);
          if (j < i + 3 || (i == 0 && j == samples - 1) || std::make_pair(i, j) >= std::make_pair(first_i, first_j))
            continue;
          const double gap = segment_distance(points[i], points[i + 1], points[j], points[j + 1]);
          // Segments near each other along the curve are near in space anyway: only pairs at
          // least 3 h apart along the curve and closer than a third of that count.
          if (gap <= touching && gap < (j - i) * h / 3) first_i = i, first_j = j, first_gap = gap;
        }
  if (first_i < samples)
    {
      std::ostringstream m;
      m << what << " crosses or touches itself: the parts near s = " << L * (first_i + 0.5) / samples << " m and s = "
        << L * (first_j + 0.5) / samples << " m come within " << first_gap << " m of each other; an arm cannot pass "
        << "through itself";
      throw InputError(entry, m.str());
    }
}

std::shared_ptr<const Curve> checked(std::shared_ptr<const Curve> curve, const CurveEntries &entries)
{
  const std::string what = "the curve (" + curve->description() + ")";
  // Absurd sizes (an expression across its pole, tan(t) at pi/2; a unit mistake) are refused
  // here, before they reach the FE model as 1e13 m long arms.
  const double L = curve->length();
  if (!(L <= max_curve_length))
    {
      std::ostringstream m;
      m << what << " is " << L << " m long; allowed: at most " << max_curve_length
        << " m (a pole of an expression inside the parameter range, e.g. tan(t) at pi/2, makes it huge)";
      throw InputError(entries.section, m.str());
    }
  auto check_position = [&](const double s) {
    const Point<3> x = curve->position(s);
    for (int d = 0; d < 3; ++d)
      if (!(std::abs(x[d]) <= max_coordinate))
        {
          std::ostringstream m;
          m << what << " reaches the coordinate " << "xyz"[d] << " = " << x[d] << " m at s = " << s
            << " m; allowed: coordinates of at most " << max_coordinate << " m in size";
          throw InputError(entries.coordinate[d], m.str());
        }
  };
  check_position(0);
  // A curve of zero length cannot carry an arm; say so instead of dividing by zero later.
  const double scale = std::max(1.0, curve->position(0).norm());
  if (!(L > 1e-12 * scale))
    throw InputError(entries.section, what + " has zero length; " + entries.advice);
  // Coordinates and the differential geometry must be finite along the whole curve. Sampled at
  // 1024 points first, then, for a curve that turns much (a helix of many turns), again at enough
  // points that the tangent turns about 0.1 rad between two (at most 65536 points).
  struct Samples
  {
    double h = 0;
    std::vector<Point<3>> points;
    std::vector<Vec3> tangents;
    std::vector<double> turns; // curvature x h at each sample [rad]
  };
  const auto sample = [&](const int n) {
    Samples c;
    c.h = L / n;
    c.points.resize(n + 1);
    c.tangents.resize(n + 1);
    c.turns.resize(n + 1);
    for (int i = 0; i <= n; ++i)
      {
        const double s = L * i / n;
        check_position(s);
        const CurveGeometry g = curve->geometry(s);
        c.points[i] = g.position;
        bool finite = std::isfinite(g.curvature) && std::isfinite(g.torsion);
        for (int d = 0; d < 3; ++d) finite = finite && std::isfinite(g.tangent[d]);
        if (!finite)
          {
            std::ostringstream m;
            m << what << " has no finite tangent or curvature at s = " << s
              << " m (a cusp, where the derivative of the position vanishes, or a singular expression); "
                 "the curve must be smooth and regular";
            throw InputError(entries.section, m.str());
          }
        c.tangents[i] = g.tangent;
        c.turns[i] = g.curvature * c.h;
      }
    return c;
  };
  Samples c = sample(1024);
  {
    // The total turn of the tangent, from the median turn between samples (a cusp's few huge
    // values do not count), sets the number of samples.
    std::vector<double> sorted = c.turns;
    std::nth_element(sorted.begin(), sorted.begin() + 512, sorted.end());
    const double total_turn = sorted[512] * 1024;
    const int needed = static_cast<int>(std::min(65536.0, std::ceil(total_turn / 0.1)));
    if (needed > 1024) c = sample(needed);
  }
  const int samples = static_cast<int>(c.points.size()) - 1;
  const double h = c.h;
  // Where the samples resolve the curve (the median turn between samples at most 0.2 rad; only a
  // helix of more than about 2000 turns is not resolved by 65536 samples, and its entries have
  // limits of their own), a turn of the tangent by more than 90 degrees between two samples is
  // a cusp or a kink: a regular curve would need a radius below 0.64 h there. A cusp such as
  // (t^3, t^2) at t = 0 reverses the tangent and was accepted (its curvature at the samples beside
  // it is large too, so no bound from the sampled curvature would catch it).
  std::vector<double> sorted = c.turns;
  std::nth_element(sorted.begin(), sorted.begin() + samples / 2, sorted.end());
  const bool resolved = sorted[samples / 2] <= 0.2;
  for (int i = 1; i <= samples && resolved; ++i)
    {
      // A sample on the cusp itself has no direction (a zero tangent): a turn of 90 degrees to
      // each side; the turn across it (i - 1 to i + 1) is the reversal.
      const bool no_direction = c.tangents[i].norm() < 0.5;
      const double turn = std::acos(std::clamp(c.tangents[i - 1] * c.tangents[i], -1.0, 1.0));
      if (turn > M_PI / 2 || no_direction)
        {
          std::ostringstream m;
          m << what << " turns its tangent by " << turn * 180 / M_PI << " degrees between s = " << L * (i - 1) / samples
            << " and " << L * i / samples << " m: a cusp or a kink; the curve must be smooth and regular";
          throw InputError(entries.section, m.str());
        }
    }
  if (resolved) refuse_self_crossing(*curve, c.points, h, L, scale, what, entries.section);
  return curve;
}

// ---- line ---------------------------------------------------------------------------------
void declare_line(ParameterHandler &prm)
{
  prm.enter_subsection("Line");
  prm.declare_entry("Start point", "0, 0, 0", three_numbers, "Start of the line: x, y, z [m], each at most 1e6 m in size.");
  prm.declare_entry("End point", "1, 0, 0", three_numbers, "End of the line: x, y, z [m], each at most 1e6 m in size.");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_line(ParameterHandler &prm, const ParseContext &where)
{
  const std::string path = where.section + "/Line/";
  prm.enter_subsection("Line");
  const Vec3 a = read_point(prm, "Start point", path), b = read_point(prm, "End point", path);
  prm.leave_subsection();
  const double L = (b - a).norm();
  const Vec3 e = L > 0 ? (b - a) / L : Vec3();
  auto y = [a, e](const Jet &s) {
    Jet3 r;
    for (int d = 0; d < 3; ++d) r[d] = Jet::constant(a[d]) + e[d] * s;
    return r;
  };
  if (!(L > 0))
    throw InputError(path + "End point", "coincides with the 'Start point': the line has zero length; "
                     "give two distinct points [m]");
  return checked(make_curve(where.section + "/Line", "line", y, 0.0, L, true),
                 entries_of(where.section + "/Line", "give two distinct points"));
}

// ---- arc ----------------------------------------------------------------------------------
void declare_arc(ParameterHandler &prm)
{
  prm.enter_subsection("Arc");
  prm.declare_entry("Radius", "1", Double(), "Radius of the circular arc [m], 1e-6 to 1e6.");
  prm.declare_entry("Angle", "1.5707963267948966", Double(),
                    "Angle swept by the arc [rad], > 0 and <= 2 pi; 6.283185307179586 (2 pi) makes a closed ring.");
  prm.declare_entry("Centre", "0, 0, 0", three_numbers, "Centre of the circle: x, y, z [m], each at most 1e6 m "
                    "in size. The arc lies in the plane z = const, starts at centre + (R, 0, 0) and turns "
                    "counter-clockwise about +z.");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_arc(ParameterHandler &prm, const ParseContext &where)
{
  const std::string path = where.section + "/Arc/";
  prm.enter_subsection("Arc");
  const double R = get_number(prm, "Radius", path, positive_length);
  const double angle = get_number(prm, "Angle", path, {0, 2 * M_PI * (1 + 1e-12), false, "rad"});
  const Vec3 c = read_point(prm, "Centre", path);
  prm.leave_subsection();
  // A full turn typed with limited digits is still a ring: snap it to 2 pi exactly.
  const double sweep = std::abs(angle - 2 * M_PI) < 1e-9 ? 2 * M_PI : angle;
  auto y = [R, c](const Jet &s) {
    Jet sn, cs;
    sin_cos((1.0 / R) * s, sn, cs);
    return Jet3{{Jet::constant(c[0]) + R * cs, Jet::constant(c[1]) + R * sn, Jet::constant(c[2])}};
  };
  return checked(make_curve(where.section + "/Arc", "circular arc", y, 0.0, R * sweep, true),
                 entries_of(where.section + "/Arc", "give a larger Radius and Angle"));
}

// ---- helix --------------------------------------------------------------------------------
void declare_helix(ParameterHandler &prm)
{
  prm.enter_subsection("Helix");
  prm.declare_entry("Radius", "0.5", Double(), "Helix radius a [m], >= 0 and <= 1e6.");
  prm.declare_entry("Pitch", "0.4", Double(), "Rise per turn h [m], at most 1e6 m in size; the helix is "
                    "(a cos t, a sin t, h t / (2 pi)) about the z axis.");
  prm.declare_entry("Turns", "1.5", Double(), "Number of turns [-], > 0 and <= 10000; the helix is at most "
                    "1e6 m long.");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_helix(ParameterHandler &prm, const ParseContext &where)
{
  const std::string path = where.section + "/Helix/";
  prm.enter_subsection("Helix");
  const double a = get_number(prm, "Radius", path, {0, max_coordinate, true, "m"});
  const double h = get_number(prm, "Pitch", path, coordinate);
  const double turns = get_number(prm, "Turns", path, {0, 1e4, false, "-"});
  prm.leave_subsection();
  const double c = h / (2 * M_PI), w = std::sqrt(a * a + c * c);
  if (!(w > 0))
    throw InputError(where.section + "/Helix", "radius and pitch are both zero: the curve has zero length; "
                     "give Radius > 0 m or Pitch != 0 m");
  // Exact arc-length form: t = s / sqrt(a^2 + c^2).
  auto y = [a, c, w](const Jet &s) {
    Jet sn, cs;
    sin_cos((1.0 / w) * s, sn, cs);
    return Jet3{{a * cs, a * sn, (c / w) * s}};
  };
  return checked(make_curve(where.section + "/Helix", "helix", y, 0.0, 2 * M_PI * turns * w, true),
                 entries_of(where.section + "/Helix", "give a larger Radius, Pitch or Turns"));
}

// ---- expressions (type I in t, type II in s) ------------------------------------------------
void declare_expressions(ParameterHandler &prm, const std::string &variable)
{
  for (const char *axis : {"x", "y", "z"})
    prm.declare_entry(std::string(axis) + "(" + variable + ")", "0", Anything(),
                      std::string("Coordinate ") + axis + " [m] as an expression in " + variable +
                        ": + - * / ^, sin cos tan exp log sqrt sinh cosh tanh atan abs, pi and the Constants; "
                        "at most 10000 characters and 200 nested levels (parentheses, function arguments, signs, "
                        "exponents). The curve must stay finite, within 1e6 m of the origin and at most 1e6 m long.");
  prm.declare_entry("Constants", "", Anything(),
                    "Named constants usable in the expressions, e.g. \"a=0.5, c=0.1\" (SI units; finite; at most "
                    "1000).");
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
    // jet(p) is a jet in p itself; compose with the incoming jet for general arguments (the
    // plain variable, the usual argument, leaves it as it is).
    if (!p.is_variable())
      for (int d = 0; d < 3; ++d) r[d] = compose(r[d], p);
    return r;
  };
  // The speed of a parametric curve needs dy/dp only: first-order jets (taylor.h).
  auto velocity = [xyz](const double p) {
    return Vec3({xyz[0].dual(p).c[1], xyz[1].dual(p).c[1], xyz[2].dual(p).c[1]});
  };
  CurveEntries entries{path, {}, ""};
  for (int d = 0; d < 3; ++d) entries.coordinate[d] = path + "/" + "xyz"[d] + "(" + variable + ")";
  const std::string all = "x(" + variable + "), y(" + variable + ") and z(" + variable + ")";
  entries.advice = all + " must describe a curve of positive length";
  // The expressions must be finite over the whole range.
  for (int i = 0; i <= 64; ++i)
    {
      const double p = begin + (end - begin) * i / 64;
      const Jet3 r = y(Jet::variable(p));
      for (int d = 0; d < 3; ++d)
        for (int k = 0; k <= 1; ++k)
          if (!std::isfinite(r[d].c[k]))
            {
              std::ostringstream m;
              m << "the expression or its derivative is not finite at " << variable << " = " << p
                << "; the curve must be smooth over the whole range";
              throw InputError(entries.coordinate[d], m.str());
            }
      const double speed = Vec3({r[0].c[1], r[1].c[1], r[2].c[1]}).norm();
      if (arc_length && std::abs(speed - 1) > 1e-6)
        {
          std::ostringstream m;
          m << "the curve " << all << " is not parametrised by arc length (|dy/ds| = " << speed << " at s = " << p
            << ", must be 1); use Kind = parametric for a general parameter";
          throw InputError(path, m.str());
        }
    }
  auto excerpt = [](const Expression &e) { return base::printable_excerpt(e.text(), 40); };
  return checked(make_curve(path, std::string(arc_length ? "arc-length" : "parametric") + " curve (" + excerpt(xyz[0]) +
                              ", " + excerpt(xyz[1]) + ", " + excerpt(xyz[2]) + ")",
                            y, begin, end, arc_length, std::vector<double>{}, velocity),
                 entries);
}

void declare_parametric(ParameterHandler &prm)
{
  prm.enter_subsection("Parametric");
  declare_expressions(prm, "t");
  prm.declare_entry("Parameter start", "0", Double(), "First value of the parameter t [-], at most 1e6 in size.");
  prm.declare_entry("Parameter end", "1", Double(), "Last value of the parameter t [-], > start, at most 1e6 in size.");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_parametric(ParameterHandler &prm, const ParseContext &where)
{
  const std::string path = where.section + "/Parametric/";
  prm.enter_subsection("Parametric");
  const NumberRange parameter{-1e6, 1e6, true, "-"};
  const double t0 = get_number(prm, "Parameter start", path, parameter);
  const double t1 = get_number(prm, "Parameter end", path, parameter);
  if (!(t1 > t0))
    {
      prm.leave_subsection();
      throw InputError(path + "Parameter end", "must be greater than 'Parameter start'");
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
  prm.declare_entry("Length", "1", Double(), "Length L of the curve [m], 1e-6 to 1e6; s runs over [0, L].");
  prm.leave_subsection();
}
std::shared_ptr<const Curve> create_arc_length(ParameterHandler &prm, const ParseContext &where)
{
  prm.enter_subsection("Arc length");
  try
    {
      const double L = get_number(prm, "Length", where.section + "/Arc length/", positive_length);
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
  prm.declare_entry("Points file", "", dealii::Patterns::FileName(dealii::Patterns::FileName::input),
                    "Text file with one point \"x y z\" [m] per line (blanks or commas; # starts a "
                    "comment), relative to the parameter file's directory. A natural cubic spline in "
                    "chord length interpolates the points. At most 100000 points, each coordinate at most "
                    "1e6 m in size; at most 64 MiB. Give either this or 'Inline points'.");
  prm.declare_entry("Inline points", "", Anything(),
                    "The points inline instead of a file: \"x y z; x y z; ...\" [m], blanks or commas between "
                    "the coordinates of a point, ';' between points (a reduced body file stores its splines "
                    "so). The same limits as a points file: 2 to 100000 points, consecutive points distinct, "
                    "each coordinate finite and at most 1e6 m in size. Give either this or 'Points file'.");
  prm.leave_subsection();
}

/// The points of the "Inline points" entry: "x y z; x y z; ..." (see declare_spline).
std::vector<Point<3>> inline_points(const std::string &text, const std::string &entry)
{
  std::vector<Point<3>> points;
  for (const auto &item : base::split(text, ';'))
    {
      const std::string where = "point " + std::to_string(points.size() + 1);
      if (points.size() == max_spline_points)
        throw InputError(entry, "more than " + std::to_string(max_spline_points) + " points; at most " +
                                  std::to_string(max_spline_points) + " are allowed (a cubic spline needs far fewer)");
      const auto w = base::words(item);
      if (w.size() != 3)
        throw InputError(entry, where + " is not three numbers \"x y z\" [m]: '" + base::printable_excerpt(item) + "'");
      Point<3> p;
      for (int d = 0; d < 3; ++d)
        {
          p[d] = base::parse_number(w[d], entry, "a coordinate [m] of " + where);
          if (!(std::abs(p[d]) <= max_coordinate))
            {
              std::ostringstream m;
              m << where << ": coordinate " << p[d] << " m; allowed: coordinates of at most " << max_coordinate
                << " m in size";
              throw InputError(entry, m.str());
            }
        }
      points.push_back(p);
    }
  if (points.size() < 2)
    throw InputError(entry, std::to_string(points.size()) + " points; a spline needs at least 2");
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i].distance(points[i - 1]) == 0)
      throw InputError(entry, "points " + std::to_string(i) + " and " + std::to_string(i + 1) +
                                " coincide; consecutive points must differ");
  return points;
}

std::shared_ptr<const Curve> create_spline(ParameterHandler &prm, const ParseContext &where)
{
  prm.enter_subsection("Spline");
  std::string file = base::trim(prm.get("Points file"));
  const std::string inline_text = prm.get("Inline points");
  prm.leave_subsection();
  const std::string file_entry = where.section + "/Spline/Points file", points_entry = where.section + "/Spline/Inline points";
  const bool has_points = !base::trim(inline_text).empty();
  if (file.empty() == !has_points)
    throw InputError(file_entry, has_points ? "give either 'Points file' or 'Inline points', not both"
                                            : "no points: give a 'Points file' or 'Inline points'");
  const std::string entry = has_points ? points_entry : file_entry;
  std::vector<Point<3>> points;
  if (has_points)
    points = inline_points(inline_text, entry);
  else
    {
      if (file[0] != '/' && !where.directory.empty()) file = where.directory + "/" + file;
      points = read_points(file, entry);
    }
  try
    {
      return checked(make_spline_curve(points), entries_of(entry, "give points that are further apart"));
    }
  catch (const CurveError &e)
    {
      throw InputError(entry, e.what());
    }
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
    {"spline", "cubic spline through points (read from a file, or given inline)", declare_spline, create_spline}};
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
