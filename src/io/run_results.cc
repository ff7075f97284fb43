// Results of a multibody run (run_results.h).
#include <base/input_error.h>
#include <io/hdf5_file.h>
#include <io/run_results.h>

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

std::vector<double> monitor_row(const multibody::MonitorValues &m, const double balance_error)
{
  return {m.position_residual, m.velocity_residual, m.normalisation_drift, m.kinetic, m.gravity, m.strain,
          m.springs, m.work_applied, m.work_drivers, m.dissipated, balance_error};
}

std::string joined(const std::vector<std::string> &names)
{
  std::string s;
  for (const auto &n : names) s += (s.empty() ? "" : "; ") + n;
  return s;
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
  file << "\n" << std::flush; // readable up to here if the run fails later
  if (!file) throw InputError("-o / Output/Directory", "cannot write '" + name + "' (is the disk full?)");
}

RunRecorder::RunRecorder(const multibody::System &s, const std::vector<std::unique_ptr<multibody::Probe>> &p,
                         OutputFolder &folder)
  : system(s), probes(p), monitor_columns(monitor_names.size())
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
}

double RunRecorder::bytes_per_row(const multibody::System &system, const std::size_t n_probes)
{
  const double kept = 1 + system.size() + 6.0 * system.n_joints() + monitor_names.size() + 6.0 * n_probes;
  const double text = 2 + monitor_names.size() + 6.0 * n_probes;
  return 8 * kept + 20 * text;
}

void RunRecorder::record(const double t, const Vector<double> &y, const multibody::MonitorValues &m, const double balance_error)
{
  time.push_back(t);
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
  max_balance_error = std::max(max_balance_error, std::abs(balance_error));

  if (!probe_csv) return;
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
      joint.reaction(system.joint_q(j, y), system.own_q_of(j, y), t, lambda.data(), force, torque);
      for (unsigned int a = 0; a < 3; ++a) reactions.push_back(force[a]);
      for (unsigned int a = 0; a < 3; ++a) reactions.push_back(torque[a]);
    }
}

void RunRecorder::write_hdf5(OutputFolder &folder) const
{
  const std::string path = folder.add_file("results.h5");
  if (!is_first_process()) return;
  try
    {
      Hdf5File f(path, Hdf5File::Mode::create);
      const hsize_t n = time.size(), nq = system.n_q(), nv = system.n_v(), nm = system.n_lambda() + system.n_mu();
      f.set_attribute("/", "format", "FlexTrack multibody results");
      f.set_attribute("/", "format_version", 1LL);
      f.set_attribute("/", "units", "SI: m, kg, s, N, rad");
      f.write("/time", {n}, time.data());
      std::vector<std::string> names;
      for (unsigned int i = 0; i < nq; ++i) names.push_back(system.component_name(i));
      f.write("/coordinates", {n, nq}, coordinates.data());
      f.set_attribute("/coordinates", "names", joined(names));
      names.clear();
      for (unsigned int i = 0; i < nv; ++i) names.push_back(system.component_name(nq + i));
      f.write("/velocities", {n, nv}, velocities.data());
      f.set_attribute("/velocities", "names", joined(names));
      names.clear();
      for (unsigned int i = 0; i < nm; ++i) names.push_back(system.component_name(nq + nv + i));
      f.write("/multipliers", {n, nm}, multipliers.data());
      f.set_attribute("/multipliers", "names", joined(names));
      f.create_group("/monitors");
      for (std::size_t i = 0; i < monitor_names.size(); ++i)
        {
          f.write("/monitors/" + monitor_names[i], {n}, monitor_columns[i].data());
          f.set_attribute("/monitors/" + monitor_names[i], "unit", monitor_units[i]);
        }
      f.create_group("/reactions");
      const hsize_t nj = system.n_joints();
      for (hsize_t j = 0; j < nj; ++j)
        {
          std::vector<double> force(3 * n), torque(3 * n);
          for (hsize_t r = 0; r < n; ++r)
            for (unsigned int a = 0; a < 3; ++a)
              {
                force[3 * r + a] = reactions[(r * nj + j) * 6 + a];
                torque[3 * r + a] = reactions[(r * nj + j) * 6 + 3 + a];
              }
          const std::string g = "/reactions/" + system.joint(j).name();
          f.create_group(g);
          f.write(g + "/force", {n, 3}, force.data());
          f.write(g + "/torque", {n, 3}, torque.data());
        }
      f.create_group("/probes");
      const hsize_t np = probes.size();
      for (hsize_t p = 0; p < np; ++p)
        {
          std::vector<double> position(3 * n), velocity(3 * n);
          for (hsize_t r = 0; r < n; ++r)
            for (unsigned int a = 0; a < 3; ++a)
              {
                position[3 * r + a] = probe_values[(r * np + p) * 6 + a];
                velocity[3 * r + a] = probe_values[(r * np + p) * 6 + 3 + a];
              }
          const std::string g = "/probes/" + probes[p]->name();
          f.create_group(g);
          f.set_attribute(g, "frame", probes[p]->frame_name());
          f.write(g + "/position", {n, 3}, position.data());
          f.write(g + "/velocity", {n, 3}, velocity.data());
        }
      f.close(); // written to disk here (io/hdf5_file.h)
    }
  catch (const std::runtime_error &e)
    {
      throw InputError("-o / Output/Directory", std::string("cannot write 'results.h5': ") + e.what());
    }
}
} // namespace flextrack::io
