// The animation of a multibody run (animation_writer.h).
#include <io/animation_writer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <sstream>

namespace flextrack::io
{
using dealii::Point;
using multibody::Vector3;

namespace
{
std::string number(const double v)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", v);
  return text;
}

std::string frame_name(const unsigned int frame)
{
  std::ostringstream s;
  s << "animation_" << std::setw(5) << std::setfill('0') << frame << ".vtu";
  return s.str();
}

/// Base64 (RFC 4648) of @p bytes.
std::string base64(const std::string &bytes)
{
  static const char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve(4 * (bytes.size() + 2) / 3);
  for (std::size_t i = 0; i < bytes.size(); i += 3)
    {
      const std::size_t left = std::min<std::size_t>(3, bytes.size() - i);
      std::uint32_t block = 0;
      for (std::size_t j = 0; j < 3; ++j)
        block = (block << 8) | (j < left ? static_cast<unsigned char>(bytes[i + j]) : 0u);
      for (std::size_t j = 0; j < 4; ++j) out += j <= left ? alphabet[(block >> (18 - 6 * j)) & 63] : '=';
    }
  return out;
}

/// A binary VTK XML DataArray: base64 of the 64-bit byte count followed by the raw values
/// (little endian, the byte order of every machine FlexTrack is built on; the header says so).
template <typename T>
std::string data_array(const std::string &type, const std::string &name, const unsigned int components,
                       const std::vector<T> &values)
{
  std::string bytes(sizeof(std::uint64_t) + values.size() * sizeof(T), '\0');
  const std::uint64_t n = values.size() * sizeof(T);
  std::memcpy(bytes.data(), &n, sizeof(n));
  if (n) std::memcpy(bytes.data() + sizeof(n), values.data(), n);
  std::ostringstream s;
  s << "<DataArray type=\"" << type << "\"" << (name.empty() ? "" : " Name=\"" + name + "\"")
    << " NumberOfComponents=\"" << components << "\" NumberOfTuples=\"" << values.size() / components
    << "\" format=\"binary\">\n" << base64(bytes) << "\n</DataArray>\n";
  return s.str();
}

/// Names go into XML attributes and text: the characters XML reserves are escaped.
std::string xml_text(const std::string &text)
{
  std::string out;
  for (const char c : text)
    switch (c)
      {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += (static_cast<unsigned char>(c) < 32 ? ' ' : c);
      }
  return out;
}

Vector3 vec(const double x, const double y, const double z)
{
  Vector3 v;
  v[0] = x, v[1] = y, v[2] = z;
  return v;
}

double extent(const std::vector<Point<3>> &points)
{
  if (points.empty()) return 0;
  Point<3> lo = points[0], hi = points[0];
  for (const auto &p : points)
    for (unsigned int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
  return lo.distance(hi);
}

constexpr double steel_density = 7850; // [kg/m^3], the cube a point mass is drawn as

/// Sides of the box of equal mass and principal moments, a_i = sqrt(6 (J_j + J_k - J_i) / m).
std::array<double, 3> inertia_box_sides(const reduction::InertiaInvariants &inv)
{
  const auto J = inv.inertia_about_centre_of_mass();
  std::array<double, 3> side;
  for (unsigned int i = 0; i < 3; ++i)
    {
      const unsigned int j = (i + 1) % 3, k = (i + 2) % 3;
      side[i] = std::sqrt(std::max(6 * (J[j][j] + J[k][k] - J[i][i]) / inv.mass, 0.0));
    }
  return side;
}
} // namespace

AnimationWriter::AnimationWriter(const multibody::System &s) : system(s)
{
  // Flexible bodies' drawings first: their size sets the smallest side of point-like things.
  double scale = 0, largest_section = 0;
  std::vector<const multibody::FloatingBody *> bodies(system.n_bodies(), nullptr);
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    bodies[b] = dynamic_cast<const multibody::FloatingBody *>(&system.body(b));
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      if (!bodies[b] || !bodies[b]->source() || bodies[b]->source()->points.empty()) continue;
      const auto &reduced = *bodies[b]->source();
      for (const auto &arm : reduced.arms)
        for (const auto &[y, z] : arm.section_outline) largest_section = std::max(largest_section, 2 * std::hypot(y, z));
      scale = std::max(scale, extent(reduced.points));
    }
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    if (bodies[b] && !(bodies[b]->source() && !bodies[b]->source()->points.empty()))
      for (const double side : inertia_box_sides(bodies[b]->invariants())) scale = std::max(scale, side);
  min_side = std::max({0.03 * scale, 2 * largest_section, 1e-6});
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      // "--" may not appear inside an XML comment
      std::string name = xml_text(system.body(b).name());
      for (std::size_t at; (at = name.find("--")) != std::string::npos;) name.replace(at, 2, "- ");
      body_legend += (b > 1 ? ", " : "") + std::to_string(b) + " = " + name;
    }

  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      if (!bodies[b]) continue;
      const auto &body = *bodies[b];
      Drawing d;
      d.body = b;
      if (body.source() && !body.source()->points.empty())
        {
          const auto &reduced = *body.source();
          const bool with_modes = body.n_modes() > 0;
          add_surface(d, reduced, with_modes);
          for (const auto &[i, mass] : reduced.point_masses)
            {
              const double side = std::max(std::cbrt(mass / steel_density), min_side);
              add_box(d, reduced.interfaces[i].position, {{side, side, side}},
                      with_modes ? &reduced.interfaces[i].modes : nullptr);
            }
          std::ostringstream what;
          what << (reduced.quads.empty() ? "" : "surface, ") << reduced.arms.size() << " arm tube(s), "
               << reduced.point_masses.size() << " point mass cube(s)" << (with_modes ? ", deformed" : ", rigid");
          d.what = what.str();
        }
      else
        {
          auto side = inertia_box_sides(body.invariants());
          for (double &s : side) s = std::max(s, min_side);
          add_box(d, body.invariants().centre_of_mass(), side, nullptr);
          std::ostringstream what;
          what << std::setprecision(3) << "box " << side[0] << " x " << side[1] << " x " << side[2] << " m";
          d.what = what.str();
        }
      drawings.push_back(std::move(d));
    }
}

std::string AnimationWriter::description() const
{
  std::ostringstream s;
  for (const auto &d : drawings)
    s << "    " << d.body << " " << system.body(d.body).name() << ": " << d.what << "\n";
  return s.str();
}

void AnimationWriter::append_point_modes(Drawing &d, const unsigned int first, const unsigned int n,
                                         const std::function<Vector3(unsigned int k, unsigned int i)> &mode) const
{
  // point_modes is ordered (k P + i) 3 + d: with P grown, every mode's block moves.
  const unsigned int P = d.points.size();
  std::vector<double> grown(n * P * 3, 0.0);
  for (unsigned int k = 0; k < n; ++k)
    {
      for (unsigned int i = 0; i < first; ++i)
        for (unsigned int a = 0; a < 3; ++a) grown[(k * P + i) * 3 + a] = d.point_modes[(k * first + i) * 3 + a];
      for (unsigned int i = first; i < P; ++i)
        {
          const Vector3 m = mode(k, i);
          for (unsigned int a = 0; a < 3; ++a) grown[(k * P + i) * 3 + a] = m[a];
        }
    }
  d.point_modes = std::move(grown);
}

void AnimationWriter::add_box(Drawing &d, const Point<3> &centre, const std::array<double, 3> sides,
                              const dealii::FullMatrix<double> *modes) const
{
  const unsigned int first = d.points.size();
  const unsigned int n = modes ? modes->n() : 0;
  std::vector<double> corner_modes;
  for (unsigned int corner = 0; corner < 8; ++corner)
    {
      Vector3 o;
      for (unsigned int i = 0; i < 3; ++i) o[i] = ((corner >> i) & 1 ? 0.5 : -0.5) * sides[i];
      d.points.push_back(centre + o);
    }
  // Corner bit i = +x_i; faces listed counter-clockwise seen from outside.
  const unsigned int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto &f : faces)
    {
      d.cells.push_back({first + f[0], first + f[1], first + f[2], first + f[3]});
      d.types.push_back(vtk_quad);
    }
  if (d.point_modes.empty() && n == 0) return;
  // Mode shapes of the new corners: the point's translation plus its rotation times the offset
  // (none for a box on a body drawn with modes by its other parts).
  const unsigned int n_all = d.point_modes.empty() ? n : d.point_modes.size() / (3 * first);
  append_point_modes(d, first, n_all, [&](const unsigned int k, const unsigned int i) {
    if (!modes || k >= n) return Vector3();
    const Vector3 u = vec((*modes)(0, k), (*modes)(1, k), (*modes)(2, k));
    const Vector3 theta = vec((*modes)(3, k), (*modes)(4, k), (*modes)(5, k));
    return Vector3(u + dealii::cross_product_3d(theta, d.points[i] - centre));
  });
}

void AnimationWriter::add_surface(Drawing &d, const reduction::ReducedBody &reduced, const bool with_modes) const
{
  // The solid's points and quads; arm centre lines only for arms without an outline (a file
  // of an arm built in code): the others are drawn as tubes.
  d.points = reduced.points;
  if (with_modes) d.point_modes = reduced.point_modes;
  for (const auto &q : reduced.quads)
    {
      d.cells.emplace_back(q.begin(), q.end());
      d.types.push_back(vtk_quadratic_quad);
    }
  bool all_outlined = true;
  for (const auto &arm : reduced.arms) all_outlined = all_outlined && !arm.section_outline.empty();
  if (!all_outlined)
    for (const auto &l : reduced.lines)
      {
        d.cells.emplace_back(l.begin(), l.end());
        d.types.push_back(vtk_line);
      }
  for (const auto &arm : reduced.arms)
    if (!arm.section_outline.empty()) add_tube(d, arm, reduced.n_modes(), with_modes);
}

void AnimationWriter::add_tube(Drawing &d, const reduction::ArmModeData &arm, const unsigned int n,
                               const bool with_modes) const
{
  // Nodes in order of arc length (each cell's nodes sorted by xi; a shared vertex once).
  const unsigned int per_cell = arm.xi.size();
  std::vector<unsigned int> order(per_cell);
  for (unsigned int j = 0; j < per_cell; ++j) order[j] = j;
  std::sort(order.begin(), order.end(), [&](unsigned int a, unsigned int b) { return arm.xi[a] < arm.xi[b]; });
  std::vector<unsigned int> nodes;
  std::vector<double> arc;
  for (unsigned int c = 0; c < arm.n_cells(); ++c)
    for (unsigned int o = (c == 0 ? 0 : 1); o < per_cell; ++o)
      {
        nodes.push_back(c * per_cell + order[o]);
        arc.push_back(arm.cell_s[c] + arm.xi[order[o]] * (arm.cell_s[c + 1] - arm.cell_s[c]));
      }
  auto position = [&](const unsigned int i) {
    return vec(arm.positions[3 * nodes[i]], arm.positions[3 * nodes[i] + 1], arm.positions[3 * nodes[i] + 2]);
  };
  // Section axes: the arm's own section frame when the file knows it, otherwise a frame carried
  // along the polyline without twist (only the orientation of a non-round section depends on it).
  std::vector<Vector3> y_axes(nodes.size()), z_axes(nodes.size());
  Vector3 carried;
  for (unsigned int i = 0; i < nodes.size(); ++i)
    {
      Vector3 t, y;
      if (arm.curve && arm.frame)
        {
          const auto g = arm.curve->geometry(std::min(arc[i], arm.curve->length()));
          t = g.tangent;
          y = arm.frame->y_axis(g);
        }
      else
        {
          const unsigned int a = i == 0 ? 0 : i - 1, b = std::min<unsigned int>(i + 1, nodes.size() - 1);
          t = position(b) - position(a);
          t /= std::max(t.norm(), 1e-300);
          if (i == 0) carried = std::abs(t[0]) < 0.9 ? vec(1, 0, 0) : vec(0, 1, 0);
          y = carried - (carried * t) * t;
          y /= std::max(y.norm(), 1e-300);
          carried = y;
        }
      y_axes[i] = y;
      z_axes[i] = dealii::cross_product_3d(t, y);
    }

  const unsigned int K = arm.section_outline.size(), first = d.points.size(), rings = nodes.size();
  std::vector<Vector3> offsets;
  for (unsigned int i = 0; i < rings; ++i)
    for (const auto &[oy, oz] : arm.section_outline)
      {
        offsets.push_back(oy * y_axes[i] + oz * z_axes[i]);
        d.points.push_back(Point<3>(position(i) + offsets.back()));
      }
  for (unsigned int i = 0; i + 1 < rings; ++i)
    for (unsigned int k = 0; k < K; ++k)
      {
        const unsigned int a = first + i * K, b = first + (i + 1) * K;
        d.cells.push_back({a + k, a + (k + 1) % K, b + (k + 1) % K, b + k});
        d.types.push_back(vtk_quad);
      }
  std::vector<unsigned int> start_cap, end_cap;
  for (unsigned int k = 0; k < K; ++k)
    start_cap.push_back(first + K - 1 - k), end_cap.push_back(first + (rings - 1) * K + k);
  d.cells.push_back(start_cap), d.types.push_back(vtk_polygon);
  d.cells.push_back(end_cap), d.types.push_back(vtk_polygon);

  if (!with_modes) return;
  // A ring follows its node: translation u plus the section's rotation theta times the offset.
  append_point_modes(d, first, n, [&](const unsigned int k, const unsigned int p) {
    const unsigned int ring = (p - first) / K;
    const double *v = &arm.values[(nodes[ring] * n + k) * 6];
    return Vector3(vec(v[0], v[1], v[2]) + dealii::cross_product_3d(vec(v[3], v[4], v[5]), offsets[p - first]));
  });
}

void AnimationWriter::add_frame(const double t, const dealii::Vector<double> &y, OutputFolder &folder)
{
  std::vector<double> points, displacement, velocity;
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
  std::vector<std::int32_t> body_ids;
  std::size_t n_points = 0;
  for (const auto &d : drawings)
    {
      const auto &body = dynamic_cast<const multibody::FloatingBody &>(system.body(d.body));
      const auto f = body.frame(system.q_of(d.body, y), system.v_of(d.body, y));
      const std::size_t P = d.points.size(), n = d.point_modes.empty() ? 0 : body.n_modes();
      for (std::size_t i = 0; i < P; ++i)
        {
          Vector3 u, u_dot;
          for (std::size_t k = 0; k < n; ++k)
            for (unsigned int a = 0; a < 3; ++a)
              {
                u[a] += d.point_modes[(k * P + i) * 3 + a] * f.eta[k];
                u_dot[a] += d.point_modes[(k * P + i) * 3 + a] * f.eta_dot[k];
              }
          const Vector3 x = Vector3(d.points[i]) + u;
          const Vector3 X = f.R + f.A * x, U = f.A * u;
          const Vector3 V = f.R_dot + f.A * (dealii::cross_product_3d(f.omega, x) + u_dot);
          for (unsigned int a = 0; a < 3; ++a)
            {
              points.push_back(X[a]);
              displacement.push_back(U[a]);
              velocity.push_back(V[a]);
            }
        }
      for (std::size_t c = 0; c < d.cells.size(); ++c)
        {
          for (const unsigned int p : d.cells[c]) connectivity.push_back(n_points + p);
          offsets.push_back(connectivity.size());
          types.push_back(d.types[c]);
          body_ids.push_back(d.body);
        }
      n_points += P;
    }
  // The body names go into a comment: a String array names them for ParaView, but meshio (and
  // other VTU readers) refuse the whole file for it.
  std::ostringstream vtu;
  vtu << "<?xml version=\"1.0\"?>\n<!-- FlexTrack " FLEXTRACK_VERSION ": multibody animation, t = " << number(t)
      << " s; cell data 'body': " << body_legend
      << " -->\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "<UnstructuredGrid>\n<FieldData>\n" << data_array("Float64", "TimeValue", 1, std::vector<double>{t})
      << "</FieldData>\n<Piece NumberOfPoints=\"" << n_points << "\" NumberOfCells=\"" << types.size() << "\">\n"
      << "<PointData Vectors=\"displacement\">\n" << data_array("Float64", "displacement", 3, displacement)
      << data_array("Float64", "velocity", 3, velocity) << "</PointData>\n"
      << "<CellData Scalars=\"body\">\n" << data_array("Int32", "body", 1, body_ids) << "</CellData>\n"
      << "<Points>\n" << data_array("Float64", "", 3, points) << "</Points>\n<Cells>\n"
      << data_array("Int64", "connectivity", 1, connectivity) << data_array("Int64", "offsets", 1, offsets)
      << data_array("UInt8", "types", 1, types) << "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  folder.add_text(frame_name(times.size()), vtu.str());
  times.push_back(t);
}

void AnimationWriter::finish(OutputFolder &folder) const
{
  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n";
  for (std::size_t k = 0; k < times.size(); ++k)
    pvd << "<DataSet timestep=\"" << number(times[k]) << "\" group=\"\" part=\"0\" file=\"" << frame_name(k) << "\"/>\n";
  pvd << "</Collection>\n</VTKFile>\n";
  folder.add_text("animation.pvd", pvd.str());
}
} // namespace flextrack::io
