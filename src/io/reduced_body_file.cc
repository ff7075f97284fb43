#include <base/names.h>
#include <io/checksummed_hdf5.h>
#include <base/input_error.h>
#include <io/output_folder.h>
#include <io/reduced_body_file.h>
#include <reduction/arm_geometry.h>
#include <reduction/plausibility.h>

#include <hdf5.h>
#include <mpi.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cerrno>
#include <cstring>
#include <filesystem>

namespace flextrack::io
{
using namespace dealii;
using reduction::ReducedBody;

namespace
{
std::vector<double> flatten(const FullMatrix<double> &A)
{
  std::vector<double> v;
  for (unsigned int i = 0; i < A.m(); ++i)
    for (unsigned int j = 0; j < A.n(); ++j) v.push_back(A(i, j));
  return v;
}

FullMatrix<double> unflatten(const std::vector<double> &v, const unsigned int m, const unsigned int n)
{
  FullMatrix<double> A(m, n);
  for (unsigned int i = 0; i < m; ++i)
    for (unsigned int j = 0; j < n; ++j) A(i, j) = v[i * n + j];
  return A;
}

std::vector<double> tensor_data(const Tensor<2, 3> &T)
{
  std::vector<double> v;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j) v.push_back(T[i][j]);
  return v;
}

Tensor<2, 3> tensor_of(const double *v)
{
  Tensor<2, 3> T;
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j) T[i][j] = v[3 * i + j];
  return T;
}

void write_file(const ReducedBody &b, const std::string &name)
{
  ChecksummedWriter f(name);
  const hsize_t n = b.n_modes();
  f.set_attribute("/", "format", reduced_body_format);
  f.set_attribute("/", "format_version", reduced_body_format_version);
  f.set_attribute("/", "flextrack_version", FLEXTRACK_VERSION);
  f.set_attribute("/", "input_hash", b.input_hash);
  f.set_attribute("/", "method", b.method);
  f.set_attribute("/", "source", b.source);
  f.set_attribute("/", "units", "SI: m, kg, s, N, rad");
  f.set_attribute("/", "n_modes", static_cast<long long>(n));
  f.set_attribute("/", "n_full_dofs", b.n_full_dofs);
  f.set_attribute("/", "n_body_dofs", b.n_body_dofs);
  f.set_attribute("/", "n_normal", b.n_normal);
  f.set_attribute("/", "n_interface", b.n_interface);
  f.set_attribute("/", "n_track", b.n_track);

  f.create_group("/reduced");
  f.write("/reduced/stiffness", {n, n}, flatten(b.stiffness).data());
  f.write("/reduced/mass", {n, n}, flatten(b.mass).data());
  f.write("/reduced/damping", {n, n}, flatten(b.damping).data());
  f.write("/reduced/frequencies_hz", {n}, b.frequencies_hz.data());
  if (!b.geometric_stiffness.empty())
    {
      std::vector<double> G;
      for (const auto &g : b.geometric_stiffness)
        for (const double x : flatten(g)) G.push_back(x);
      f.write("/reduced/geometric_stiffness", {12, n, n}, G.data());
    }

  const auto &inv = b.invariants;
  f.create_group("/inertia");
  f.write("/inertia/mass", {1}, &inv.mass);
  f.write("/inertia/first_moment", {3}, &inv.first_moment[0]);
  f.write("/inertia/inertia_origin", {3, 3}, tensor_data(inv.inertia_origin).data());
  f.write("/inertia/I3", {3, n}, flatten(inv.I3).data());
  f.write("/inertia/I4", {3, n}, flatten(inv.I4).data());
  std::vector<double> P, Q;
  for (const auto &t : inv.P) for (const double x : tensor_data(t)) P.push_back(x);
  for (const auto &t : inv.Q) for (const double x : tensor_data(t)) Q.push_back(x);
  f.write("/inertia/P", {n, 3, 3}, P.data());
  f.write("/inertia/Q", {n, n, 3, 3}, Q.data());

  for (const auto &[group, points] : {std::make_pair("/interfaces", &b.interfaces), std::make_pair("/output_points", &b.output_points)})
    {
      f.create_group(group);
      for (unsigned int i = 0; i < points->size(); ++i)
        {
          const auto &p = (*points)[i];
          const std::string g = std::string(group) + "/" + p.name;
          f.create_group(g);
          f.set_attribute(g, "index", i);
          f.write(g + "/position", {3}, &p.position[0]);
          f.write(g + "/modes", {6, n}, flatten(p.modes).data());
        }
    }

  f.create_group("/arms");
  for (unsigned int a = 0; a < b.arms.size(); ++a)
    {
      const auto &arm = b.arms[a];
      const std::string g = "/arms/" + arm.name;
      const hsize_t nodes = arm.n_cells() * arm.xi.size();
      f.create_group(g);
      f.set_attribute(g, "index", a);
      f.set_attribute(g, "track_stations", static_cast<long long>(arm.track_stations));
      f.write(g + "/cell_arc_length", {arm.cell_s.size()}, arm.cell_s.data());
      f.write(g + "/reference_nodes", {arm.xi.size()}, arm.xi.data());
      f.write(g + "/positions", {nodes, 3}, arm.positions.data());
      f.write(g + "/modes", {nodes, n, 6}, arm.values.data());
      if (!arm.geometry_parameters.empty()) f.write_text(g + "/geometry_parameters", arm.geometry_parameters);
      std::vector<double> outline;
      for (const auto &[y, z] : arm.section_outline) outline.insert(outline.end(), {y, z});
      f.write(g + "/section_outline", {arm.section_outline.size(), 2}, outline.data());
    }

  f.create_group("/drawing");
  const hsize_t P_count = b.points.size();
  std::vector<double> points;
  for (const auto &p : b.points) points.insert(points.end(), {p[0], p[1], p[2]});
  std::vector<unsigned int> quads, lines;
  for (const auto &q : b.quads) quads.insert(quads.end(), q.begin(), q.end());
  for (const auto &l : b.lines) lines.insert(lines.end(), l.begin(), l.end());
  f.write("/drawing/points", {P_count, 3}, points.data());
  f.write("/drawing/quads", {b.quads.size(), 8}, quads.data());
  f.write("/drawing/lines", {b.lines.size(), 2}, lines.data());
  f.write("/drawing/mode_displacements", {n, P_count, 3}, b.point_modes.data());
  std::vector<unsigned int> mass_interfaces;
  std::vector<double> masses;
  for (const auto &[i, m] : b.point_masses) mass_interfaces.push_back(i), masses.push_back(m);
  f.write("/drawing/point_mass_interfaces", {masses.size()}, mass_interfaces.data());
  f.write("/drawing/point_masses", {masses.size()}, masses.data());
  f.close();
}

/// Members of @p group in the order of their "index" attribute.
std::vector<std::string> in_index_order(ChecksummedReader &f, const std::string &group)
{
  const auto names = f.members(group);
  if (names.size() > 100000) throw std::runtime_error("group '" + group + "' has too many members");
  std::vector<std::string> ordered(names.size());
  for (const auto &name : names)
    {
      // Names go into other tools' inputs (MBDyn, VTU): only the documented character set.
      if (!base::is_valid_name(name))
        throw std::runtime_error("group '" + group + "' has a member named '" + base::printable_excerpt(name) +
                                 "'; a name has " + base::name_rule());
      const long long i = f.integer_attribute(group + "/" + name, "index");
      if (i < 0 || i >= static_cast<long long>(names.size()) || !ordered[i].empty())
        throw std::runtime_error("group '" + group + "/" + name + "' has an invalid 'index'");
      ordered[i] = name;
    }
  return ordered;
}

/// A reduced body as read, and the checksums that say whether the file is as it was written.
struct ReadBody
{
  ReducedBody body;
  std::string stored_checksum, computed_checksum;
};

/// Reads every item, checking shapes, types, finiteness, names and arm geometry; the checksum
/// and the physical checks follow in read_reduced_body.
ReadBody read_file(const std::string &name, const bool rebuild_geometry = true)
{
  ChecksummedReader f(name);
  std::string format;
  try
    {
      format = f.string_attribute("/", "format");
    }
  catch (const std::runtime_error &)
    {
      throw std::runtime_error("an HDF5 file, but not a FlexTrack reduced body (no root attribute 'format' = '" +
                               reduced_body_format + "'); write one with 'flextrack reduce FILE.prm'");
    }
  if (format != reduced_body_format)
    throw std::runtime_error("its format is '" + format + "', not '" + reduced_body_format + "'");
  const long long version = f.integer_attribute("/", "format_version");
  if (version != reduced_body_format_version)
    throw std::runtime_error("format version " + std::to_string(version) + " is not supported (this FlexTrack reads " +
                             std::to_string(reduced_body_format_version) + "); reduce the body again");
  ReadBody result;
  try
    {
      result.stored_checksum = f.stored_checksum();
    }
  catch (const std::runtime_error &e)
    {
      throw std::runtime_error(std::string("it has no valid content checksum (") + e.what() + ")");
    }
  ReducedBody &b = result.body;
  f.string_attribute("/", "flextrack_version"); // not used, but part of the checksum
  f.string_attribute("/", "units");
  b.input_hash = f.string_attribute("/", "input_hash");
  b.method = f.string_attribute("/", "method");
  b.source = f.string_attribute("/", "source");
  // Counts are checked against the datasets before anything is allocated from them.
  const long long n_modes = f.integer_attribute("/", "n_modes");
  const auto stiffness_shape = f.shape("/reduced/stiffness");
  if (stiffness_shape.size() != 2 || static_cast<long long>(stiffness_shape[0]) != n_modes ||
      stiffness_shape[1] != stiffness_shape[0])
    throw std::runtime_error("attribute 'n_modes' = " + std::to_string(n_modes) +
                             " does not match the shape of '/reduced/stiffness'");
  const hsize_t n = n_modes;
  auto count = [&](const char *name, const long long limit) {
    const long long v = f.integer_attribute("/", name);
    if (v < 0 || v > limit)
      throw std::runtime_error("attribute '" + std::string(name) + "' = " + std::to_string(v) + " is outside 0 ... " +
                               std::to_string(limit));
    return static_cast<unsigned int>(v);
  };
  constexpr long long max_dofs = 2000000000;
  b.n_full_dofs = count("n_full_dofs", max_dofs);
  b.n_body_dofs = count("n_body_dofs", max_dofs);
  b.n_normal = count("n_normal", n_modes);
  b.n_interface = count("n_interface", n_modes);
  b.n_track = count("n_track", n_modes);

  b.stiffness = unflatten(f.read_doubles("/reduced/stiffness", {n, n}), n, n);
  b.mass = unflatten(f.read_doubles("/reduced/mass", {n, n}), n, n);
  b.damping = unflatten(f.read_doubles("/reduced/damping", {n, n}), n, n);
  b.frequencies_hz = f.read_doubles("/reduced/frequencies_hz", {n});
  if (f.exists("/reduced/geometric_stiffness"))
    {
      const auto G = f.read_doubles("/reduced/geometric_stiffness", {12, n, n});
      for (unsigned int c = 0; c < 12; ++c)
        b.geometric_stiffness.push_back(
          unflatten(std::vector<double>(G.begin() + c * n * n, G.begin() + (c + 1) * n * n), n, n));
    }

  auto &inv = b.invariants;
  inv.mass = f.read_doubles("/inertia/mass", {1})[0];
  const auto s = f.read_doubles("/inertia/first_moment", {3});
  for (unsigned int d = 0; d < 3; ++d) inv.first_moment[d] = s[d];
  inv.inertia_origin = tensor_of(f.read_doubles("/inertia/inertia_origin", {3, 3}).data());
  inv.I3 = unflatten(f.read_doubles("/inertia/I3", {3, n}), 3, n);
  inv.I4 = unflatten(f.read_doubles("/inertia/I4", {3, n}), 3, n);
  const auto P = f.read_doubles("/inertia/P", {n, 3, 3}), Q = f.read_doubles("/inertia/Q", {n, n, 3, 3});
  for (hsize_t k = 0; k < n; ++k) inv.P.push_back(tensor_of(&P[9 * k]));
  for (hsize_t k = 0; k < n * n; ++k) inv.Q.push_back(tensor_of(&Q[9 * k]));

  for (const auto &[group, points] : {std::make_pair("/interfaces", &b.interfaces), std::make_pair("/output_points", &b.output_points)})
    for (const auto &name : in_index_order(f, group))
      {
        const std::string g = std::string(group) + "/" + name;
        const auto x = f.read_doubles(g + "/position", {3});
        points->push_back({name, Point<3>(x[0], x[1], x[2]), unflatten(f.read_doubles(g + "/modes", {6, n}), 6, n)});
      }
  for (const auto &name : in_index_order(f, "/arms"))
    {
      const std::string g = "/arms/" + name;
      reduction::ArmModeData arm;
      arm.name = name;
      arm.n_modes = n;
      const auto cells = f.shape(g + "/cell_arc_length"), nodes = f.shape(g + "/reference_nodes");
      if (cells.size() != 1 || cells[0] < 2 || nodes.size() != 1 || nodes[0] < 2 || nodes[0] > 8)
        throw std::runtime_error("arm '" + name + "': invalid cell_arc_length or reference_nodes");
      arm.cell_s = f.read_doubles(g + "/cell_arc_length", cells);
      arm.xi = f.read_doubles(g + "/reference_nodes", nodes);
      const hsize_t count = (cells[0] - 1) * nodes[0];
      arm.positions = f.read_doubles(g + "/positions", {count, 3});
      arm.values = f.read_doubles(g + "/modes", {count, n, 6});
      // The exact curve and section frame, rebuilt from their text and checked against the
      // nodes; without the text (an arm built in code) both stay unknown.
      if (f.exists(g + "/geometry_parameters"))
        try
          {
            arm.geometry_parameters =
              f.read_text(g + "/geometry_parameters", reduction::max_geometry_parameters_bytes);
            if (rebuild_geometry) reduction::rebuild_arm_geometry(arm);
          }
        catch (const std::runtime_error &e)
          {
            throw std::runtime_error("arm '" + name + "': " + e.what());
          }
      const long long stations = f.integer_attribute(g, "track_stations");
      if (stations < 0 || stations > 100000)
        throw std::runtime_error("arm '" + name + "': attribute 'track_stations' = " + std::to_string(stations) +
                                 " is not from 0 to 100000");
      arm.track_stations = static_cast<unsigned int>(stations);
      const auto outline_shape = f.shape(g + "/section_outline");
      if (outline_shape.size() != 2 || outline_shape[1] != 2 || outline_shape[0] < 3 || outline_shape[0] > 64)
        throw std::runtime_error("arm '" + name + "': dataset 'section_outline' is not K x 2 with 3 <= K <= 64");
      const auto outline = f.read_doubles(g + "/section_outline", outline_shape);
      for (hsize_t k = 0; k < outline_shape[0]; ++k)
        {
          if (!(std::abs(outline[2 * k]) <= 1e3 && std::abs(outline[2 * k + 1]) <= 1e3))
            throw std::runtime_error("arm '" + name + "': 'section_outline' holds a corner beyond 1000 m or not a number");
          arm.section_outline.push_back({{outline[2 * k], outline[2 * k + 1]}});
        }
      b.arms.push_back(std::move(arm));
    }

  const auto points_shape = f.shape("/drawing/points");
  if (points_shape.size() != 2 || points_shape[1] != 3) throw std::runtime_error("dataset '/drawing/points' is not P x 3");
  const hsize_t P_count = points_shape[0];
  const auto points = f.read_doubles("/drawing/points", {P_count, 3});
  for (hsize_t i = 0; i < P_count; ++i) b.points.emplace_back(points[3 * i], points[3 * i + 1], points[3 * i + 2]);
  const auto quads_shape = f.shape("/drawing/quads"), lines_shape = f.shape("/drawing/lines");
  if (quads_shape.size() != 2 || quads_shape[1] != 8 || lines_shape.size() != 2 || lines_shape[1] != 2)
    throw std::runtime_error("datasets '/drawing/quads' (Q x 8) or '/drawing/lines' (E x 2) have the wrong shape");
  const auto quads = f.read_unsigned("/drawing/quads", quads_shape), lines = f.read_unsigned("/drawing/lines", lines_shape);
  for (hsize_t i = 0; i < quads_shape[0]; ++i)
    {
      std::array<unsigned int, 8> q;
      for (unsigned int j = 0; j < 8; ++j)
        if ((q[j] = quads[8 * i + j]) >= P_count) throw std::runtime_error("'/drawing/quads' refers to a missing point");
      b.quads.push_back(q);
    }
  for (hsize_t i = 0; i < lines_shape[0]; ++i)
    {
      if (lines[2 * i] >= P_count || lines[2 * i + 1] >= P_count)
        throw std::runtime_error("'/drawing/lines' refers to a missing point");
      b.lines.push_back({{lines[2 * i], lines[2 * i + 1]}});
    }
  b.point_modes = f.read_doubles("/drawing/mode_displacements", {n, P_count, 3});
  const auto masses_shape = f.shape("/drawing/point_masses");
  if (masses_shape.size() != 1) throw std::runtime_error("dataset '/drawing/point_masses' is not a list");
  const auto mass_interfaces = f.read_unsigned("/drawing/point_mass_interfaces", masses_shape);
  const auto masses = f.read_doubles("/drawing/point_masses", masses_shape);
  for (hsize_t i = 0; i < masses_shape[0]; ++i)
    {
      if (mass_interfaces[i] >= b.interfaces.size())
        throw std::runtime_error("'/drawing/point_mass_interfaces' refers to a missing interface");
      if (!(masses[i] > 0 && masses[i] < 1e12))
        throw std::runtime_error("'/drawing/point_masses' holds a mass that is not in (0, 1e12) kg");
      b.point_masses.emplace_back(mass_interfaces[i], masses[i]);
    }
  result.computed_checksum = f.computed_checksum();
  return result;
}

/// The physical checks run first, so that a damaged body is refused naming what is wrong with
/// it; the checksum then says whether the file changed after it was written. Throws
/// std::runtime_error.
void verify_contents(const ReadBody &read)
{
  const bool intact = read.stored_checksum == read.computed_checksum;
  const std::string mismatch = "checksum mismatch: the file was changed or damaged after it was written "
                               "(content_checksum " +
                               read.stored_checksum + ", its contents sum to " + read.computed_checksum +
                               "); reduce the body again";
  try
    {
      reduction::check_physical_plausibility(read.body);
    }
  catch (const std::runtime_error &e)
    {
      throw std::runtime_error(std::string(e.what()) + (intact ? "" : "; also " + mismatch));
    }
  if (!intact) throw std::runtime_error(mismatch);
}
} // namespace

void write_reduced_body(const ReducedBody &body, const std::string &file)
{
  try
    {
      write_atomically(file, [&](const std::string &temporary) { write_file(body, temporary); });
    }
  catch (const std::runtime_error &e)
    {
      throw InputError("", std::string("cannot write the reduced body: ") + e.what(), file);
    }
}

namespace
{
/// Reads @p file once in a forked child process and reports whether that child was killed by a
/// signal (and which; -1: it died otherwise, e.g. a sanitizer's exit). The HDF5 library itself (1.10) can crash on a damaged file before any
/// check of ours runs (the fuzz target found a local heap overwritten with 0xff: SIGSEGV in
/// H5Lexists); a crash of the child becomes a clear refusal in the parent. Not done once MPI runs
/// (forking an MPI process is not supported) or where fork fails: then the file is read directly.
int signal_of_trial_read(const std::string &file)
{
  int mpi_started = 0;
  MPI_Initialized(&mpi_started);
  if (mpi_started) return 0;
  // The library is set up here, once in the parent: a child that set it up itself would do it
  // again for every body it reads (about 10 ms each), and the parent too.
  H5open();
  const pid_t child = fork();
  if (child < 0) return 0;
  if (child == 0)
    {
      try
        {
          read_file(file, false); // the HDF5 reads; rebuilding the curves (half the time) is no HDF5 call
        }
      catch (...)
        {
        }
      _exit(0);
    }
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
    if (errno != EINTR) return 0;
  if (WIFSIGNALED(status)) return WTERMSIG(status);
  return WIFEXITED(status) && WEXITSTATUS(status) != 0 ? -1 : 0;
}
} // namespace

ReducedBody read_reduced_body(const std::string &file)
{
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw InputError("", "is not a regular file (a folder or a device such as /dev/zero): a reduced body is an HDF5 "
                         "file written by 'flextrack reduce FILE.prm'", file);
  if (!std::filesystem::is_regular_file(file, ec))
    throw InputError("", "the reduced body file does not exist (write it with 'flextrack reduce FILE.prm')", file);
  if (const int signal = signal_of_trial_read(file))
    throw InputError("", std::string("not a valid reduced body: the HDF5 library crashed reading it (") +
                           (signal > 0 ? "signal " + std::to_string(signal) + ", " + strsignal(signal) : "abnormal exit") +
                           "): the file is damaged; write it again with 'flextrack reduce FILE.prm'",
                     file);
  try
    {
      auto read = read_file(file);
      verify_contents(read);
      return std::move(read.body);
    }
  catch (const std::runtime_error &e)
    {
      throw InputError("", std::string("not a valid reduced body: ") + e.what(), file);
    }
}
} // namespace flextrack::io
