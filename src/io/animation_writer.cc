// The animation of a multibody run (animation_writer.h).
#include <io/animation_writer.h>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

namespace flextrack::io
{
using dealii::Point;

namespace
{
std::string number(const double v)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", v); // a picture: 9 digits are plenty
  return text;
}

std::string frame_name(const unsigned int frame)
{
  std::ostringstream s;
  s << "animation_" << std::setw(5) << std::setfill('0') << frame << ".vtu";
  return s.str();
}

constexpr unsigned int vtk_line = 3, vtk_quad = 9, vtk_quadratic_quad = 23;
} // namespace

AnimationWriter::AnimationWriter(const multibody::System &s) : system(s)
{
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      const auto *body = dynamic_cast<const multibody::FloatingBody *>(&system.body(b));
      if (!body) continue;
      if (body->source() && !body->source()->points.empty())
        add_surface(b, *body->source(), body->n_modes() > 0);
      else
        add_box(b, body->invariants());
    }
}

void AnimationWriter::add_box(const unsigned int body, const reduction::InertiaInvariants &inv)
{
  Drawing d;
  d.body = body;
  const Point<3> c = inv.centre_of_mass();
  const auto J = inv.inertia_about_centre_of_mass();
  double side[3];
  for (unsigned int i = 0; i < 3; ++i)
    {
      const unsigned int j = (i + 1) % 3, k = (i + 2) % 3;
      side[i] = std::sqrt(std::max(6 * (J[j][j] + J[k][k] - J[i][i]) / inv.mass, 0.0));
    }
  const double smallest = 0.02 * std::max({side[0], side[1], side[2], 1e-3}); // a flat body stays visible
  for (unsigned int corner = 0; corner < 8; ++corner)
    {
      Point<3> p = c;
      for (unsigned int i = 0; i < 3; ++i) p[i] += ((corner >> i) & 1 ? 0.5 : -0.5) * std::max(side[i], smallest);
      d.points.push_back(p);
    }
  // Corner bit i = +x_i; faces listed counter-clockwise seen from outside.
  const unsigned int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto &f : faces)
    {
      d.cells.push_back({f[0], f[1], f[2], f[3]});
      d.types.push_back(vtk_quad);
    }
  drawings.push_back(std::move(d));
}

void AnimationWriter::add_surface(const unsigned int body, const reduction::ReducedBody &reduced, const bool with_modes)
{
  Drawing d;
  d.body = body;
  d.points = reduced.points;
  if (with_modes) d.point_modes = reduced.point_modes;
  for (const auto &q : reduced.quads)
    {
      d.cells.emplace_back(q.begin(), q.end());
      d.types.push_back(vtk_quadratic_quad);
    }
  for (const auto &l : reduced.lines)
    {
      d.cells.emplace_back(l.begin(), l.end());
      d.types.push_back(vtk_line);
    }
  drawings.push_back(std::move(d));
}

void AnimationWriter::add_frame(const double t, const dealii::Vector<double> &y, OutputFolder &folder)
{
  std::ostringstream points, connectivity, offsets, types, body_ids;
  std::size_t n_points = 0, n_cells = 0, offset = 0;
  for (const auto &d : drawings)
    {
      const auto &body = dynamic_cast<const multibody::FloatingBody &>(system.body(d.body));
      const auto f = body.frame(system.q_of(d.body, y));
      const std::size_t P = d.points.size(), n = d.point_modes.empty() ? 0 : body.n_modes();
      for (std::size_t i = 0; i < P; ++i)
        {
          multibody::Vector3 x(d.points[i]);
          for (std::size_t k = 0; k < n; ++k)
            for (unsigned int a = 0; a < 3; ++a) x[a] += d.point_modes[(k * P + i) * 3 + a] * f.eta[k];
          const multibody::Vector3 X = f.R + f.A * x;
          points << number(X[0]) << " " << number(X[1]) << " " << number(X[2]) << "\n";
        }
      for (std::size_t c = 0; c < d.cells.size(); ++c)
        {
          for (std::size_t j = 0; j < d.cells[c].size(); ++j) connectivity << (j ? " " : "") << n_points + d.cells[c][j];
          connectivity << "\n";
          offsets << (offset += d.cells[c].size()) << "\n";
          types << d.types[c] << "\n";
          body_ids << d.body << "\n";
        }
      n_points += P;
      n_cells += d.cells.size();
    }
  std::ostringstream vtu;
  vtu << "<?xml version=\"1.0\"?>\n<!-- FlexTrack " FLEXTRACK_VERSION ": multibody animation, t = " << number(t)
      << " s -->\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << n_points << "\" NumberOfCells=\"" << n_cells << "\">\n"
      << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n" << points.str()
      << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n"
      << connectivity.str() << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n"
      << offsets.str() << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n" << types.str()
      << "</DataArray>\n</Cells>\n<CellData Scalars=\"body\">\n<DataArray type=\"Int32\" Name=\"body\" format=\"ascii\">\n"
      << body_ids.str() << "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
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
