// Results of a multibody run (run_results.h).
#include <base/input_error.h>
#include <io/hdf5_file.h>
#include <io/run_results.h>
#include <multibody/track_joint.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace flextrack::io
{
using dealii::Vector;

namespace
{
const std::vector<std::string> monitor_names = {
  "position_residual", "velocity_residual", "normalisation_drift", "kinetic_energy", "gravity_energy",
  "strain_energy", "spring_energy", "work_applied", "work_drivers", "dissipated", "energy_balance_error"};
const std::vector<std::string> monitor_units = {"m_or_rad", "m_per_s_or_rad_per_s", "1", "J", "J", "J", "J", "J", "J", "J", "1"};

/// The joints that slide on a track (each writes its contact force).
std::vector<unsigned int> track_joint_indices(const multibody::System &system)
{
  std::vector<unsigned int> indices;
  for (unsigned int j = 0; j < system.n_joints(); ++j)
    if (dynamic_cast<const multibody::TrackJoint *>(&system.joint(j))) indices.push_back(j);
  return indices;
}

std::vector<double> monitor_row(const multibody::MonitorValues &m, const double balance_error)
{
  return {m.position_residual, m.velocity_residual, m.normalisation_drift, m.kinetic, m.gravity, m.strain,
          m.springs, m.work_applied, m.work_drivers, m.dissipated, balance_error};
}

} // namespace

IncrementalCsv::IncrementalCsv(OutputFolder &folder, const std::string &file_name, const std::vector<std::string> &columns)
  : name(file_name)
{
  const std::string path = folder.add_file(name);
  if (!is_first_process()) return;
  file.open(path, std::ios::binary);
  if (!file) throw InputError("-o / Output/Directory", "cannot write '" + name + "': " + std::strerror(errno));
  for (std::size_t i = 0; i < columns.size(); ++i) file << (i ? "," : "") << columns[i];
  file << "\n" << std::flush;
}

void IncrementalCsv::add_row(const std::vector<double> &values)
{
  if (!file.is_open()) return;
  for (std::size_t i = 0; i < values.size(); ++i) file << (i ? "," : "") << csv_number(values[i]);
  file << "\n" << std::flush; // readable up to here if the run fails or is killed later
  if (!file) throw InputError("-o / Output/Directory", "cannot write '" + name + "' (is the disk full?)");
}

RunRecorder::RunRecorder(const multibody::System &s, const std::vector<std::unique_ptr<multibody::Probe>> &p,
                         OutputFolder &folder, const double expected_rows)
  : system(s), probes(p), track_joints(track_joint_indices(s)), monitor_columns(monitor_names.size())
{
  if (!probes.empty())
    {
      std::vector<std::string> columns{"time_s"};
      for (const auto &probe : probes)
        for (const char *q : {"x_m", "y_m", "z_m", "vx_m_per_s", "vy_m_per_s", "vz_m_per_s"})
          columns.push_back(probe->name() + "_" + q);
      probe_csv = std::make_unique<IncrementalCsv>(folder, "probes.csv", columns);
    }
  std::vector<std::string> columns{"time_s"};
  for (std::size_t i = 0; i < monitor_names.size(); ++i) columns.push_back(monitor_names[i] + "_" + monitor_units[i]);
  monitor_csv = std::make_unique<IncrementalCsv>(folder, "monitors.csv", columns);
  // A block of about 4 MiB of numbers between writes of results.h5.
  const double values_per_row = 1 + system.size() + 6.0 * system.n_joints() + 3.0 * track_joints.size() + monitor_names.size() + 6.0 * probes.size();
  rows_per_block = static_cast<unsigned int>(std::clamp((4 << 20) / (8 * values_per_row), 1.0, 4096.0));
  const std::string path = folder.add_file("results.h5");
  if (is_first_process()) create_hdf5(path, static_cast<unsigned long long>(std::clamp(expected_rows, 1.0, 1e9)));
}

RunRecorder::~RunRecorder() = default;

void RunRecorder::create_hdf5(const std::string &path, const unsigned long long expected_rows)
{
  try
    {
      hdf5 = std::make_unique<Hdf5File>(path, Hdf5File::Mode::create_on_disk);
      auto &f = *hdf5;
      const hsize_t nq = system.n_q(), nv = system.n_v(), nm = system.n_lambda() + system.n_mu();
      f.set_attribute("/", "format", "FlexTrack multibody results");
      f.set_attribute("/", "format_version", 1LL);
      f.set_attribute("/", "units", "SI: m, kg, s, N, rad");
      f.create_growing("/time", 0, expected_rows);
      f.set_attribute("/time", "unit", "s");
      const auto named = [&](const std::string &set, const hsize_t first, const hsize_t n) {
        f.create_growing(set, n, expected_rows);
        std::vector<std::string> names;
        for (hsize_t i = 0; i < n; ++i) names.push_back(system.component_name(first + i));
        f.set_attribute(set, "names", names); // one per column
      };
      named("/coordinates", 0, nq);
      named("/velocities", nq, nv);
      named("/multipliers", nq + nv, nm);
      f.create_group("/monitors");
      for (std::size_t i = 0; i < monitor_names.size(); ++i)
        {
          f.create_growing("/monitors/" + monitor_names[i], 0, expected_rows);
          f.set_attribute("/monitors/" + monitor_names[i], "unit", monitor_units[i]);
        }
      f.create_group("/reactions");
      for (unsigned int j = 0; j < system.n_joints(); ++j)
        {
          const std::string g = "/reactions/" + system.joint(j).name();
          f.create_group(g);
          f.create_growing(g + "/force", 3, expected_rows);
          f.set_attribute(g + "/force", "unit", "N");
          f.create_growing(g + "/torque", 3, expected_rows);
          f.set_attribute(g + "/torque", "unit", "N m");
        }
      for (const unsigned int j : track_joints)
        {
          const std::string d = "/reactions/" + system.joint(j).name() + "/contact_force";
          f.create_growing(d, 3, expected_rows);
          f.set_attribute(d, "unit", "N");
          f.set_attribute(d, "components", "the force on body 1 in the track's frame at the contact: tangential (along "
                                           "increasing s), normal along the section y axis, normal along the section "
                                           "z axis (t x y); of a double_arm_sleeve the frame of its contact on body "
                                           "2's arm");
        }
      f.create_group("/probes");
      for (const auto &probe : probes)
        {
          const std::string g = "/probes/" + probe->name();
          f.create_group(g);
          f.set_attribute(g, "frame", probe->frame_name());
          f.create_growing(g + "/position", 3, expected_rows);
          f.set_attribute(g + "/position", "unit", "m");
          f.set_attribute(g + "/position", "frame", probe->frame_name());
          f.create_growing(g + "/velocity", 3, expected_rows);
          f.set_attribute(g + "/velocity", "unit", "m/s");
          f.set_attribute(g + "/velocity", "frame", probe->frame_name());
        }
    }
  catch (const std::runtime_error &e)
    {
      throw InputError("-o / Output/Directory", std::string("cannot write 'results.h5': ") + e.what());
    }
}

double RunRecorder::bytes_per_row(const multibody::System &system, const std::size_t n_probes)
{
  const double kept = 1 + system.size() + 6.0 * system.n_joints() + 3.0 * track_joint_indices(system).size() +
                      monitor_names.size() + 6.0 * n_probes; // a track joint writes its contact force too
  const double text = 2 + monitor_names.size() + 6.0 * n_probes;
  return 8 * kept + 20 * text;
}

void RunRecorder::record(const double t, const Vector<double> &y, const multibody::MonitorValues &m, const double balance_error)
{
  time.push_back(t);
  ++rows_recorded;
  time_of_last_row = t;
  const unsigned int nq = system.n_q(), nv = system.n_v();
  coordinates.insert(coordinates.end(), y.begin(), y.begin() + nq);
  velocities.insert(velocities.end(), y.begin() + nq, y.begin() + nq + nv);
  multipliers.insert(multipliers.end(), y.begin() + nq + nv, y.end());
  record_reactions(t, y);

  const auto monitors = monitor_row(m, balance_error);
  for (std::size_t i = 0; i < monitors.size(); ++i) monitor_columns[i].push_back(monitors[i]);
  std::vector<double> row{t};
  row.insert(row.end(), monitors.begin(), monitors.end());
  monitor_csv->add_row(row);
  max_position_residual = std::max(max_position_residual, m.position_residual);
  max_velocity_residual = std::max(max_velocity_residual, m.velocity_residual);
  max_normalisation_drift = std::max(max_normalisation_drift, m.normalisation_drift);

  if (probe_csv)
    {
      row = {t};
      for (const auto &probe : probes)
        {
          const auto v = probe->evaluate(system, y);
          for (unsigned int a = 0; a < 3; ++a) row.push_back(v.position[a]);
          for (unsigned int a = 0; a < 3; ++a) row.push_back(v.velocity[a]);
        }
      probe_values.insert(probe_values.end(), row.begin() + 1, row.end());
      probe_csv->add_row(row);
    }
  if (time.size() >= rows_per_block) write_block();
}

void RunRecorder::record_reactions(const double t, const Vector<double> &y)
{
  // Force and torque that each joint exerts on its first body at its marker [N, N m], global; the
  // multipliers of dropped (redundant) equations are zero, so those reactions are one of many
  // possible. A joint with own coordinates (a track contact's arc length s) is evaluated at them:
  // its rows' gradients, and so its reaction, depend on where the contact is.
  const unsigned int l0 = system.n_q() + system.n_v();
  for (unsigned int j = 0; j < system.n_joints(); ++j)
    {
      const auto &joint = system.joint(j);
      std::vector<double> lambda(joint.n_equations(), 0.0);
      const auto &active = system.active_equations(j);
      for (unsigned int r = 0; r < active.size(); ++r) lambda[active[r]] = y[l0 + system.multiplier_offset(j) + r];
      multibody::Vector3 force, torque;
      if (std::find(track_joints.begin(), track_joints.end(), j) != track_joints.end())
        {
          // The track marker's axes are (d2, d3, t): tangential first, then the two normals.
          std::array<multibody::Vector3, 3> axes;
          static_cast<const multibody::GenericJoint &>(joint).reaction(system.joint_q(j, y), system.own_q_of(j, y), t,
                                                                       lambda.data(), force, torque, axes);
          contact_forces.insert(contact_forces.end(), {force * axes[2], force * axes[0], force * axes[1]});
        }
      else
        joint.reaction(system.joint_q(j, y), system.own_q_of(j, y), t, lambda.data(), force, torque);
      for (unsigned int a = 0; a < 3; ++a) reactions.push_back(force[a]);
      for (unsigned int a = 0; a < 3; ++a) reactions.push_back(torque[a]);
    }
}

void RunRecorder::write_block()
{
  const hsize_t n = time.size();
  if (hdf5 && n > 0)
    try
      {
        auto &f = *hdf5;
        f.append_rows("/time", n, time.data());
        f.append_rows("/coordinates", n, coordinates.data());
        f.append_rows("/velocities", n, velocities.data());
        f.append_rows("/multipliers", n, multipliers.data());
        for (std::size_t i = 0; i < monitor_names.size(); ++i)
          f.append_rows("/monitors/" + monitor_names[i], n, monitor_columns[i].data());
        // Reactions and probes are recorded row by row for all joints / probes; each has its own
        // datasets [n x 3].
        const auto split = [&](const std::vector<double> &rows, const std::size_t items, const std::size_t item,
                               const unsigned int offset) {
          std::vector<double> part(3 * n);
          for (hsize_t r = 0; r < n; ++r)
            for (unsigned int a = 0; a < 3; ++a) part[3 * r + a] = rows[(r * items + item) * 6 + offset + a];
          return part;
        };
        const std::size_t nj = system.n_joints(), np = probes.size();
        for (std::size_t j = 0; j < nj; ++j)
          {
            const std::string g = "/reactions/" + system.joint(j).name();
            f.append_rows(g + "/force", n, split(reactions, nj, j, 0).data());
            f.append_rows(g + "/torque", n, split(reactions, nj, j, 3).data());
          }
        for (std::size_t k = 0; k < track_joints.size(); ++k)
          {
            std::vector<double> part(3 * n);
            for (hsize_t r = 0; r < n; ++r)
              for (unsigned int a = 0; a < 3; ++a) part[3 * r + a] = contact_forces[(r * track_joints.size() + k) * 3 + a];
            f.append_rows("/reactions/" + system.joint(track_joints[k]).name() + "/contact_force", n, part.data());
          }
        for (std::size_t p = 0; p < np; ++p)
          {
            const std::string g = "/probes/" + probes[p]->name();
            f.append_rows(g + "/position", n, split(probe_values, np, p, 0).data());
            f.append_rows(g + "/velocity", n, split(probe_values, np, p, 3).data());
          }
      }
    catch (const std::runtime_error &e)
      {
        throw InputError("-o / Output/Directory", std::string("cannot write 'results.h5': ") + e.what());
      }
  for (auto *block : {&time, &coordinates, &velocities, &multipliers, &reactions, &contact_forces, &probe_values})
    block->clear();
  for (auto &column : monitor_columns) column.clear();
}

void RunRecorder::finish()
{
  write_block();
  if (!hdf5) return;
  try
    {
      hdf5->close();
    }
  catch (const std::runtime_error &e)
    {
      throw InputError("-o / Output/Directory", std::string("cannot write 'results.h5': ") + e.what());
    }
}
} // namespace flextrack::io
