// Test helper: structured hex20 meshes written as complete CalculiX input files, and a reader of
// CalculiX's eigenvalue table. The mesh is the image of an nx x ny x nz grid on the unit cube
// under a map; mid-side nodes are mapped too, so curved maps give curved edges.
#pragma once

#include <deal.II/base/point.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace test_support
{
using Map = std::function<dealii::Point<3>(double, double, double)>;

/// Writes PATH: nodes, C3D20 elements, node set FIX (the face xi = 0), steel, and a *FREQUENCY
/// step for n_modes modes.
inline void write_hex20_inp(const std::string &path, unsigned int nx, unsigned int ny, unsigned int nz, const Map &map,
                            unsigned int n_modes = 10)
{
  const unsigned int NX = 2 * nx + 1, NY = 2 * ny + 1, NZ = 2 * nz + 1;
  auto id = [&](unsigned int i, unsigned int j, unsigned int k) { return 1 + i + NX * (j + NY * k); };
  std::ofstream out(path);
  out.precision(15); // CalculiX reads fields of at most 20 characters
  out << "** structured C3D20 mesh written by FlexTrack's tests\n*NODE, NSET=NALL\n";
  for (unsigned int k = 0; k < NZ; ++k)
    for (unsigned int j = 0; j < NY; ++j)
      for (unsigned int i = 0; i < NX; ++i)
        if ((i % 2) + (j % 2) + (k % 2) <= 1)
          {
            const auto p = map(double(i) / (NX - 1), double(j) / (NY - 1), double(k) / (NZ - 1));
            out << id(i, j, k) << ", " << p[0] << ", " << p[1] << ", " << p[2] << "\n";
          }
  // Abaqus C3D20 node order: corners 1-4 (bottom, counter-clockwise), 5-8 (top), then mid-sides.
  const int local[20][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2},
                            {0, 2, 2}, {1, 0, 0}, {2, 1, 0}, {1, 2, 0}, {0, 1, 0}, {1, 0, 2}, {2, 1, 2},
                            {1, 2, 2}, {0, 1, 2}, {0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}};
  out << "*ELEMENT, TYPE=C3D20, ELSET=EALL\n";
  unsigned int e = 1;
  for (unsigned int c = 0; c < nz; ++c)
    for (unsigned int b = 0; b < ny; ++b)
      for (unsigned int a = 0; a < nx; ++a, ++e)
        {
          out << e;
          // CalculiX reads at most 16 entries per line: the element number and 15 nodes.
          for (unsigned int n = 0; n < 20; ++n)
            out << (n == 15 ? ",\n" : ", ") << id(2 * a + local[n][0], 2 * b + local[n][1], 2 * c + local[n][2]);
          out << "\n";
        }
  out << "*NSET, NSET=FIX\n";
  unsigned int count = 0;
  for (unsigned int k = 0; k < NZ; ++k)
    for (unsigned int j = 0; j < NY; ++j)
      if ((j % 2) + (k % 2) <= 1) out << id(0, j, k) << (++count % 8 ? ", " : ",\n");
  out << "\n*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n"
      << "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nFIX, 1, 3\n"
      << "*STEP\n*FREQUENCY\n" << n_modes << "\n*END STEP\n";
}

/// Runs `ccx JOB` in DIR; returns the frequencies [Hz] of its .dat eigenvalue table (empty on failure).
inline std::vector<double> run_calculix(const std::string &dir, const std::string &job)
{
  const std::string command = "cd '" + dir + "' && ccx " + job + " > " + job + ".ccx.log 2>&1";
  if (std::system(command.c_str()) != 0) return {};
  std::ifstream dat(dir + "/" + job + ".dat");
  std::string line;
  std::vector<double> f;
  bool table = false;
  while (std::getline(dat, line))
    {
      if (line.find("E I G E N V A L U E   O U T P U T") != std::string::npos) { table = true; continue; }
      if (line.find("P A R T I C I P A T I O N") != std::string::npos) break;
      if (!table) continue;
      std::istringstream in(line);
      int mode;
      double eigenvalue, omega, hz;
      if (in >> mode >> eigenvalue >> omega >> hz) f.push_back(hz);
    }
  return f;
}
} // namespace test_support
