// The results of a multibody run ('flextrack run'), written through the run's OutputFolder:
//  - probes.csv and monitors.csv are written row by row and flushed after every row, so that the
//    rows before a solver failure (or a killed process: NAME.writing-PID) stay readable;
//  - results.h5 (time, coordinates, velocities, multipliers, joint reactions, monitors, probes)
//    is kept in memory and written once, at the end or at the failure.
// Layout of both in doc/multibody.md.
#pragma once

#include <io/output_folder.h>
#include <multibody/monitors.h>
#include <multibody/probe.h>
#include <multibody/system.h>

#include <deal.II/lac/vector.h>

#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::io
{
/// A CSV file written one row at a time (each row flushed).
class IncrementalCsv
{
public:
  IncrementalCsv(OutputFolder &folder, const std::string &name, const std::vector<std::string> &columns);
  void add_row(const std::vector<double> &values);

private:
  std::string name;
  std::ofstream file;
};

/// Everything the run records at an output time, for results.h5.
class RunRecorder
{
public:
  RunRecorder(const multibody::System &system, const std::vector<std::unique_ptr<multibody::Probe>> &probes,
              OutputFolder &folder);
  /// Records one output row (also into probes.csv and monitors.csv).
  void record(double t, const dealii::Vector<double> &y, const multibody::MonitorValues &monitors,
              double balance_error);
  /// Bytes one output row costs: the numbers kept for results.h5 (8 bytes each) and the text of
  /// probes.csv and monitors.csv (about 20 characters a number).
  static double bytes_per_row(const multibody::System &system, std::size_t n_probes);
  /// Writes results.h5 with the rows recorded so far.
  void write_hdf5(OutputFolder &folder) const;
  unsigned int n_rows() const { return time.size(); }
  double last_time() const { return time.empty() ? 0.0 : time.back(); }
  /// Largest constraint drift over the rows: position, velocity residual, ||p| - 1|; energy balance.
  double max_position_residual = 0, max_velocity_residual = 0, max_normalisation_drift = 0, max_balance_error = 0;

private:
  void record_reactions(double t, const dealii::Vector<double> &y);
  const multibody::System &system;
  const std::vector<std::unique_ptr<multibody::Probe>> &probes;
  std::unique_ptr<IncrementalCsv> probe_csv, monitor_csv;
  std::vector<double> time, coordinates, velocities, multipliers, reactions;
  std::vector<std::vector<double>> monitor_columns;
  std::vector<double> probe_values; // per row: per probe position (3), velocity (3)
};
} // namespace flextrack::io
