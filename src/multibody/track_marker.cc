// Kinematics of a contact sliding along an arm; see track_marker.h for the formulas.
#include <base/input_error.h>
#include <multibody/track_marker.h>

#include <sstream>
#include <stdexcept>

namespace flextrack::multibody
{
using namespace dealii;
using geometry::skew;

TrackMarker::TrackMarker(const Body &body, std::string name, std::shared_ptr<const geometry::Curve> curve_,
                         std::shared_ptr<const geometry::SectionFrame> frame_,
                         std::shared_ptr<const reduction::ArmModeField> field_, const double s0, const double s0_rate)
  : Marker(body, std::move(name)), curve(std::move(curve_)), frame(std::move(frame_)), field(std::move(field_)),
    s_start(s0), s_rate(s0_rate)
{
  for (unsigned int a = 0; a < 3; ++a) axes_offset[a][a] = 1;
  Assert(curve && frame, ExcMessage("a track needs its curve and section frame"));
  if (body.n_modes() > 0 && (!field || field->data().n_modes != body.n_modes()))
    throw std::invalid_argument("the mode fields of the track do not match the modes of body '" + body.name() + "'");
}

void TrackMarker::initial_own_coordinates(double *q, double *v) const
{
  q[0] = s_start;
  v[0] = s_rate;
}

Matrix3 TrackMarker::section_axes(const double s) const
{
  const geometry::CurveGeometry g = curve->geometry(s);
  const Vector3 d2 = frame->y_axis(s), d3 = cross_product_3d(g.tangent, d2);
  Matrix3 a;
  for (unsigned int i = 0; i < 3; ++i)
    {
      a[i][0] = d2[i];
      a[i][1] = d3[i];
      a[i][2] = g.tangent[i];
    }
  return a * axes_offset;
}

double TrackMarker::clamped(const double s, double &beyond) const
{
  const double L = curve->length(), s_on = std::clamp(s, 0.0, L);
  beyond = s - s_on;
  if (!(std::abs(beyond) <= overrun_fraction * L))
    {
      std::ostringstream m;
      m << "contact '" << name() << "' at s = " << s << " m is off its track [0, " << L << "] m";
      throw std::out_of_range(m.str());
    }
  return s_on;
}

void TrackMarker::marker_axes(const Place &place, const double beyond, std::array<Vector3, 3> &axis,
                              std::array<Vector3, 3> &axis_s, Vector3 *darboux) const
{
  const Vector3 t = place.g.tangent, t_s = place.g.derivative[1], d2 = place.d2, d2_s = place.d2_s;
  const std::array<Vector3, 3> section_end = {{d2, cross_product_3d(t, d2), t}};
  const std::array<Vector3, 3> section_s = {{d2_s, cross_product_3d(t_s, d2) + cross_product_3d(t, d2_s), t_s}};
  std::array<Vector3, 3> section; // beyond an end: continued to first order, so B stays continuous
  for (unsigned int k = 0; k < 3; ++k) section[k] = section_end[k] + beyond * section_s[k];
  for (unsigned int c = 0; c < 3; ++c)
    {
      axis[c] = axis_s[c] = Vector3();
      for (unsigned int k = 0; k < 3; ++k)
        {
          axis[c] += axes_offset[k][c] * section[k];
          axis_s[c] += axes_offset[k][c] * section_s[k];
        }
    }
  if (!darboux) return;
  *darboux = Vector3();
  for (unsigned int a = 0; a < 3; ++a) *darboux += 0.5 * cross_product_3d(section[a], section_s[a]);
}

bool TrackMarker::modal_jacobian_derivatives(const double *q, const double *own,
                                             std::vector<ModalJacobianDerivative> &d) const
{
  // evaluate() below: u, theta and their slopes are sums of the mode fields times eta, and J
  // takes them only in -A u~ and -A b_c~ (b_c = g_c + theta x g_c: the omega columns) and in
  // A u_s, A (g_c,s + theta x g_c,s + theta_s x g_c) (the s column). R enters no Jacobian.
  const unsigned int nv = body().n_v(), n = body().n_modes();
  if (nv == 0) return false; // the ground: no coordinates to differentiate by
  double beyond;
  const Place &place = place_at(clamped(own[0], beyond));
  std::array<Vector3, 3> axis, axis_s;
  marker_axes(place, beyond, axis, axis_s);
  const Matrix3 A = geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}});
  d.resize(n);
  for (unsigned int m = 0; m < n; ++m)
    {
      Vector3 phi_u, phi_t, slope_u, slope_t; // mode m's fields at the place (continued beyond an end)
      for (unsigned int c = 0; c < 3; ++c)
        {
          slope_u[c] = place.slope[6 * m + c];
          slope_t[c] = place.slope[6 * m + 3 + c];
          phi_u[c] = place.value[6 * m + c] + beyond * slope_u[c];
          phi_t[c] = place.value[6 * m + 3 + c] + beyond * slope_t[c];
        }
      ModalJacobianDerivative &dm = d[m];
      dm.omega[0] = -A * skew(phi_u);
      dm.own[0] = A * slope_u;
      for (unsigned int c = 0; c < 3; ++c)
        {
          dm.omega[1 + c] = -A * skew(cross_product_3d(phi_t, axis[c]));
          dm.own[1 + c] = A * (cross_product_3d(phi_t, axis_s[c]) + cross_product_3d(slope_t, axis[c]));
        }
    }
  return true;
}

const TrackMarker::Place &TrackMarker::place_at(const double s_on) const
{
  if (s_on == last_place.s) return last_place;
  Place &p = last_place;
  p.s = std::numeric_limits<double>::quiet_NaN(); // not valid until filled (a throw below)
  p.g = curve->geometry(s_on);
  p.d2 = frame->y_axis(p.g);
  p.d2_s = frame->y_axis_rate(p.g, p.d2);
  const unsigned int n = body().n_modes();
  p.value.assign(6 * n, 0.0);
  p.slope.assign(6 * n, 0.0);
  if (n > 0) field->evaluate(s_on, p.value.data(), p.slope.data());
  p.s = s_on;
  return p;
}

void TrackMarker::evaluate(const double *q, const double *own, MarkerKinematics &k) const
{
  const unsigned int nv = body().n_v(), n = body().n_modes(), ns = nv; // column of s'
  k.J_position.reinit(3, nv + 1);
  k.J_rotation.reinit(3, nv + 1);
  for (auto &J : k.J_axes) J.reinit(3, nv + 1);

  // The place on the curve (straight continuation within the overrun zone, see the header).
  double beyond;
  const Place &place = place_at(clamped(own[0], beyond));
  const geometry::CurveGeometry &g = place.g;
  const Vector3 t = g.tangent, t_s = g.derivative[1];
  std::array<Vector3, 3> axis, axis_s; // the marker's axes: section axes times the offset
  Vector3 darboux;                      // angular velocity of the section frame per unit s'
  marker_axes(place, beyond, axis, axis_s, &darboux);

  // Mode fields at s: u, theta and their slopes.
  Vector3 u = Vector3(g.position) + beyond * t + 0.5 * beyond * beyond * t_s, u_s = t + beyond * t_s, theta, theta_s;
  thread_local std::vector<double> value, slope; // copies that keep their storage between calls
  value = place.value;
  slope = place.slope;
  if (n > 0)
    {
      for (unsigned int i = 0; i < 6 * n; ++i) value[i] += beyond * slope[i];
      for (unsigned int m = 0; m < n; ++m)
        for (unsigned int c = 0; c < 3; ++c)
          {
            u[c] += value[6 * m + c] * q[7 + m];
            theta[c] += value[6 * m + 3 + c] * q[7 + m];
            u_s[c] += slope[6 * m + c] * q[7 + m];
            theta_s[c] += slope[6 * m + 3 + c] * q[7 + m];
          }
    }

  Matrix3 A;
  Vector3 R;
  if (nv > 0)
    {
      R = Vector3({q[0], q[1], q[2]});
      A = geometry::rotation_matrix({{q[3], q[4], q[5], q[6]}});
    }
  else
    for (unsigned int a = 0; a < 3; ++a) A[a][a] = 1; // the ground: body axes are global
  k.position = R + A * u;

  // Position and rotation rows
  const Vector3 r_s = A * u_s, w_s = A * (darboux + theta_s);
  const Matrix3 Au = -A * skew(u);
  for (unsigned int a = 0; a < 3; ++a)
    {
      k.J_position(a, ns) = r_s[a];
      k.J_rotation(a, ns) = w_s[a];
      if (nv == 0) continue;
      k.J_position(a, a) = 1;
      for (unsigned int b = 0; b < 3; ++b)
        {
          k.J_position(a, 3 + b) = Au[a][b];
          k.J_rotation(a, 3 + b) = A[a][b];
        }
      for (unsigned int m = 0; m < n; ++m)
        for (unsigned int b = 0; b < 3; ++b)
          {
            k.J_position(a, 6 + m) += A[a][b] * value[6 * m + b];
            k.J_rotation(a, 6 + m) += A[a][b] * value[6 * m + 3 + b];
          }
    }

  // Axes e_c = A b_c, b_c = g_c + theta x g_c
  for (unsigned int c = 0; c < 3; ++c)
    {
      const Vector3 b_c = axis[c] + cross_product_3d(theta, axis[c]);
      k.axes[c] = A * b_c;
      const Vector3 e_s = A * (axis_s[c] + cross_product_3d(theta, axis_s[c]) + cross_product_3d(theta_s, axis[c]));
      FullMatrix<double> &J = k.J_axes[c];
      for (unsigned int a = 0; a < 3; ++a) J(a, ns) = e_s[a];
      if (nv == 0) continue;
      const Matrix3 Ab = -A * skew(b_c), Ag = -A * skew(axis[c]);
      for (unsigned int a = 0; a < 3; ++a)
        {
          for (unsigned int b = 0; b < 3; ++b) J(a, 3 + b) = Ab[a][b];
          for (unsigned int m = 0; m < n; ++m)
            for (unsigned int b = 0; b < 3; ++b) J(a, 6 + m) += Ag[a][b] * value[6 * m + 3 + b];
        }
    }
}
} // namespace flextrack::multibody
