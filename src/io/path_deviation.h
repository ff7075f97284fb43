// How far a run's probes are from their nominal path: the same scene run a second time with every
// body rigid (Multibody/Rigid reference = true; doc/multibody.md, doc/laser_robot.md). Both runs
// record their probe positions at the same output times (t0 + k * Output interval, and the end);
// the deviation at a row is |r_run - r_rigid|. Written through the run's OutputFolder:
//  - deviation.csv: time_s, then per probe NAME: NAME_rigid_x_m, NAME_rigid_y_m, NAME_rigid_z_m,
//    NAME_deviation_m (the rows both runs reached);
//  - deviation.gp: the gnuplot script of deviation.png (two panels: the paths of both runs in the
//    x-y plane, from probes.csv and deviation.csv; the deviation [mm] against time). The program
//    runs it after the folder is committed (base/external_program.h).
#pragma once

#include <io/json.h>
#include <io/output_folder.h>
#include <multibody/probe.h>
#include <multibody/system.h>

#include <deal.II/lac/vector.h>

#include <memory>
#include <string>
#include <vector>

namespace flextrack::io
{
/// The positions of a run's probes at its output times [m, global axes or the probe's frame].
class ProbePaths
{
public:
  ProbePaths(const multibody::System &system, const std::vector<std::unique_ptr<multibody::Probe>> &probes)
    : system(system), probes(probes), positions(probes.size())
  {}
  void record(double t, const dealii::Vector<double> &y);
  unsigned int n_rows() const { return time.size(); }
  /// Position of probe @p probe at output row @p row [m].
  const multibody::Vector3 &position(unsigned int probe, unsigned int row) const { return positions[probe][row]; }

private:
  friend class PathDeviation;
  const multibody::System &system;
  const std::vector<std::unique_ptr<multibody::Probe>> &probes;
  std::vector<double> time;
  std::vector<std::vector<multibody::Vector3>> positions; ///< [probe][row]
};

/// The deviation of @p run from @p reference (the same probes, the same output times).
class PathDeviation
{
public:
  /// Compares the rows that both runs reached, up to the first whose times differ (none do for
  /// the same scene: the output times are computed alike).
  PathDeviation(const ProbePaths &run, const ProbePaths &reference);

  struct Largest
  {
    std::string probe;
    double distance = 0; ///< [m]
    double time = 0;     ///< [s] where it is reached (the first such row)
  };
  const std::vector<Largest> &largest() const { return maxima; }
  unsigned int n_rows() const { return time.size(); }

  /// deviation.csv and deviation.gp.
  void write(OutputFolder &out) const;
  /// Per probe: the largest deviation and its time, for summary.json.
  std::string json(unsigned int indent) const;

private:
  std::vector<std::string> names;
  std::vector<double> time;
  std::vector<std::vector<multibody::Vector3>> reference;  ///< [probe][row]
  std::vector<std::vector<double>> distance;               ///< [probe][row] [m]
  std::vector<Largest> maxima;
};
} // namespace flextrack::io
