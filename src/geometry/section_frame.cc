#include <base/text.h>
#include <geometry/section_frame.h>
#include <base/input_error.h>

#include <sstream>

namespace flextrack::geometry
{
namespace
{
constexpr int rmf_steps = 4096;

Vec3 project_to_section(const Vec3 &v, const Vec3 &t) { return v - (v * t) * t; }

/// One double-reflection step (Wang et al. 2008): frame vector r at (x0, t0) carried to (x1, t1).
Vec3 double_reflection(const Point<3> &x0, const Vec3 &t0, const Vec3 &r, const Point<3> &x1, const Vec3 &t1)
{
  const Vec3 v1 = x1 - x0;
  const double c1 = v1 * v1;
  if (c1 == 0) return r;
  const Vec3 rL = r - (2 / c1) * (v1 * r) * v1;
  const Vec3 tL = t0 - (2 / c1) * (v1 * t0) * v1;
  const Vec3 v2 = t1 - tL;
  const double c2 = v2 * v2;
  const Vec3 out = c2 > 0 ? rL - (2 / c2) * (v2 * rL) * v2 : rL;
  const Vec3 p = project_to_section(out, t1);
  return p / p.norm();
}
} // namespace

SectionFrame::SectionFrame(std::shared_ptr<const Curve> c, const Kind kind, const Vec3 &ref)
  : curve(std::move(c)), frame_kind(kind), reference(ref)
{
  if (kind != Kind::rotation_minimising)
    {
      // Check the frame where it will be needed, so that bad input fails before any FE work.
      for (int i = 0; i <= 1024; ++i)
        y_axis(curve->length() * i / 1024);
      return;
    }
  // Start from the reference vector projected onto the first section plane.
  const CurveGeometry g0 = curve->geometry(0.0);
  Vec3 r = project_to_section(reference, g0.tangent);
  if (r.norm() < 1e-8 * reference.norm() || reference.norm() == 0)
    throw FrameError("the reference vector is parallel to the tangent at s = 0; choose another "
                     "'Reference vector' for the rotation-minimising frame");
  r /= r.norm();
  rmf_y.reserve(rmf_steps + 1);
  rmf_y.push_back(r);
  rmf_x.push_back(g0.position);
  rmf_t.push_back(g0.tangent);
  Point<3> x = g0.position;
  Vec3 t = g0.tangent;
  const double h = curve->length() / rmf_steps;
  for (int i = 1; i <= rmf_steps; ++i)
    {
      const CurveGeometry g = curve->geometry(i * h);
      r = double_reflection(x, t, r, g.position, g.tangent);
      rmf_y.push_back(r);
      rmf_x.push_back(g.position);
      rmf_t.push_back(g.tangent);
      x = g.position;
      t = g.tangent;
    }
}

Vec3 SectionFrame::y_axis(const double s) const
{
  return y_axis(curve->geometry(s));
}

Vec3 SectionFrame::y_axis(const CurveGeometry &g) const
{
  const double s = g.s;
  switch (frame_kind)
    {
      case Kind::frenet:
        if (g.curvature * curve->length() < 1e-8)
          {
            std::ostringstream m;
            m << "the Frenet frame is undefined at s = " << s << " m, where the curvature is " << g.curvature
              << " 1/m (straight piece or inflection point); use 'Section frame/Kind = rotation minimising' "
                 "or 'fixed vector'";
            throw FrameError(m.str());
          }
        return g.normal;
      case Kind::fixed_vector:
        {
          const Vec3 p = project_to_section(reference, g.tangent);
          if (p.norm() < 1e-8 * reference.norm() || reference.norm() == 0)
            {
              std::ostringstream m;
              m << "the section reference vector is parallel to the tangent at s = " << s
                << " m; choose a 'Reference vector' that is never tangent to the curve";
              throw FrameError(m.str());
            }
          return p / p.norm();
        }
      case Kind::rotation_minimising:
        {
          const double h = curve->length() / rmf_steps;
          const int i = std::min(rmf_steps - 1, std::max(0, static_cast<int>(s / h)));
          return double_reflection(rmf_x[i], rmf_t[i], rmf_y[i], g.position, g.tangent);
        }
    }
  return Vec3();
}

Vec3 SectionFrame::y_axis_rate(const CurveGeometry &g, const Vec3 &y) const
{
  const Vec3 &t_rate = g.derivative[1]; // t' = y''
  switch (frame_kind)
    {
      case Kind::frenet:
        return -g.curvature * g.tangent + g.torsion * g.binormal;
      case Kind::rotation_minimising:
        return -(y * t_rate) * g.tangent;
      case Kind::fixed_vector:
        {
          // u = r - (r.t) t, d2 = u / |u|:  d2' = (u' - d2 (d2 . u')) / |u|
          const Vec3 u = project_to_section(reference, g.tangent);
          const Vec3 u_rate = -(reference * t_rate) * g.tangent - (reference * g.tangent) * t_rate;
          return (u_rate - (y * u_rate) * y) / u.norm();
        }
    }
  return Vec3();
}

void SectionFrame::declare_parameters(dealii::ParameterHandler &prm)
{
  prm.enter_subsection("Section frame");
  prm.declare_entry("Kind", "rotation minimising",
                    dealii::Patterns::Selection("frenet|rotation minimising|fixed vector"),
                    "Orientation of the section's y axis along the curve: 'frenet' = principal normal "
                    "(undefined where the curvature is zero), 'rotation minimising' = parallel transport of "
                    "the reference vector from s = 0 (no twist), 'fixed vector' = the reference vector "
                    "projected onto each section plane.");
  prm.declare_entry("Reference vector", "0, 0, 1", dealii::Patterns::List(dealii::Patterns::Double(), 3, 3, ","),
                    "Reference direction for the section's y axis [-] (rotation minimising: at s = 0; "
                    "fixed vector: everywhere). Not zero, each component at most 1e6 in size; must not be "
                    "parallel to the tangent.");
  prm.leave_subsection();
}

SectionFrame SectionFrame::parse_parameters(dealii::ParameterHandler &prm, std::shared_ptr<const Curve> curve,
                                            const ParseContext &where)
{
  prm.enter_subsection("Section frame");
  const std::string kind = prm.get("Kind");
  const std::string entry = where.section + "/Section frame/Reference vector";
  const auto r = base::parse_vector3(prm.get("Reference vector"), entry, "-");
  prm.leave_subsection();
  for (const double c : r) checked_number(c, entry, {-1e6, 1e6, true, "-"});
  const Vec3 ref({r[0], r[1], r[2]});
  if (!(ref.norm() > 0))
    throw InputError(entry, "the reference vector is zero; give a direction, e.g. '0, 0, 1'");
  const Kind k = kind == "frenet" ? Kind::frenet : kind == "fixed vector" ? Kind::fixed_vector : Kind::rotation_minimising;
  try
    {
      return SectionFrame(std::move(curve), k, ref);
    }
  catch (const FrameError &e)
    {
      throw InputError(where.section + "/Section frame", e.what());
    }
}
} // namespace flextrack::geometry
