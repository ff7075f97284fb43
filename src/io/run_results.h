// The results of a multibody run ('flextrack run'), written through the run's OutputFolder:
//  - probes.csv and monitors.csv are written row by row and flushed after every row, so that the
//    rows before a solver failure (or a killed process: NAME.writing-PID) stay readable;
//  - results.h5 (time, coordinates, velocities, multipliers, joint reactions, monitors, probes)
//    is written to disk in blocks of rows as the run goes (at most about 4 MiB held in memory),
//    and closed at the end or at the failure (finish()).
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

class Hdf5File;

/// Everything the run records at an output time, for results.h5.
class RunRecorder
{
public:
  /// Creates probes.csv, monitors.csv and results.h5 (under their temporary names) in @p folder;
  /// @p expected_rows (the run's estimate) sizes the storage chunks of results.h5.
  RunRecorder(const multibody::System &system, const std::vector<std::unique_ptr<multibody::Probe>> &probes,
              OutputFolder &folder, double expected_rows);
  ~RunRecorder();
  /// Records one output row (also into probes.csv and monitors.csv).
  void record(double t, const dealii::Vector<double> &y, const multibody::MonitorValues &monitors,
              double balance_error);
  /// Bytes one output row costs on disk: the numbers of results.h5 (8 bytes each) and the text of
  /// probes.csv and monitors.csv (about 20 characters a number).
  static double bytes_per_row(const multibody::System &system, std::size_t n_probes);
  /// Writes the rows not yet written and closes results.h5 (committed with the folder).
  void finish();
  unsigned int n_rows() const { return rows_recorded; }
  double last_time() const { return time_of_last_row; }
  /// Largest constraint drift over the rows: position, velocity residual, ||p| - 1|; energy balance.
  double max_position_residual = 0, max_velocity_residual = 0, max_normalisation_drift = 0;

private:
  void create_hdf5(const std::string &path, unsigned long long expected_rows);
  void record_reactions(double t, const dealii::Vector<double> &y);
  /// Appends the rows held in the block below to results.h5 and empties the block.
  void write_block();
  const multibody::System &system;
  const std::vector<std::unique_ptr<multibody::Probe>> &probes;
  std::unique_ptr<IncrementalCsv> probe_csv, monitor_csv;
  std::unique_ptr<Hdf5File> hdf5; // null on the other MPI processes
  unsigned int rows_recorded = 0, rows_per_block = 1;
  double time_of_last_row = 0;
  // The block of rows not yet in results.h5, row-major.
  std::vector<double> time, coordinates, velocities, multipliers, reactions;
  /// Track joints (indices) and, per row and track joint, the force on body 1 in the track's
  /// contact frame: tangential, normal along the section y axis, normal along the section z axis.
  const std::vector<unsigned int> track_joints;
  std::vector<double> contact_forces;
  std::vector<std::vector<double>> monitor_columns;
  std::vector<double> probe_values; // per row: per probe position (3), velocity (3)
};
} // namespace flextrack::io
