#include <base/names.h>
#include <io/vtu_export.h>

#include <cstdio>
#include <iomanip>
#include <sstream>

namespace flextrack::io
{
namespace
{
std::string number(const double v)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", v);
  return text;
}
/// @p text inside an XML comment: printable, short, and without "--" (which ends a comment).
std::string xml_comment_text(const std::string &text)
{
  std::string t = base::printable_excerpt(text, 200);
  for (std::size_t i = t.find("--"); i != std::string::npos; i = t.find("--")) t[i + 1] = '_';
  return t;
}
} // namespace

std::string mode_shapes_vtu_text(const reduction::ReducedBody &body)
{
  const std::size_t P = body.points.size(), n = body.n_modes();
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n"
      << "<!-- FlexTrack " FLEXTRACK_VERSION ": mode shapes of the reduced body of " << xml_comment_text(body.source) << " -->\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "<UnstructuredGrid>\n<FieldData>\n"
      << "<DataArray type=\"Float64\" Name=\"frequencies_Hz\" NumberOfTuples=\"" << n << "\" format=\"ascii\">\n";
  for (std::size_t k = 0; k < n; ++k) out << number(body.frequencies_hz[k]) << "\n";
  out << "</DataArray>\n</FieldData>\n"
      << "<Piece NumberOfPoints=\"" << P << "\" NumberOfCells=\"" << body.quads.size() + body.lines.size() << "\">\n"
      << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto &p : body.points) out << number(p[0]) << " " << number(p[1]) << " " << number(p[2]) << "\n";
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto &q : body.quads)
    {
      for (unsigned int j = 0; j < 8; ++j) out << (j ? " " : "") << q[j];
      out << "\n";
    }
  for (const auto &l : body.lines) out << l[0] << " " << l[1] << "\n";
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  std::size_t offset = 0;
  for (std::size_t i = 0; i < body.quads.size(); ++i) out << (offset += 8) << "\n";
  for (std::size_t i = 0; i < body.lines.size(); ++i) out << (offset += 2) << "\n";
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < body.quads.size(); ++i) out << "23\n";
  for (std::size_t i = 0; i < body.lines.size(); ++i) out << "3\n";
  out << "</DataArray>\n</Cells>\n<PointData Vectors=\"" << (n ? "mode_001" : "") << "\">\n";
  for (std::size_t k = 0; k < n; ++k)
    {
      out << "<DataArray type=\"Float64\" Name=\"mode_" << std::setw(3) << std::setfill('0') << k + 1
          << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < P; ++i)
        {
          const double *u = &body.point_modes[(k * P + i) * 3];
          out << number(u[0]) << " " << number(u[1]) << " " << number(u[2]) << "\n";
        }
      out << "</DataArray>\n";
    }
  out << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return out.str();
}
} // namespace flextrack::io
