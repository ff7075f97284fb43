// Deviation of a run's probe paths from the rigid reference run (path_deviation.h).
#include <io/path_deviation.h>

#include <io/gnuplot.h>

#include <cmath>
#include <sstream>

namespace flextrack::io
{
void ProbePaths::record(const double t, const dealii::Vector<double> &y)
{
  time.push_back(t);
  for (std::size_t p = 0; p < probes.size(); ++p) positions[p].push_back(probes[p]->evaluate(system, y).position);
}

PathDeviation::PathDeviation(const ProbePaths &run, const ProbePaths &rigid)
  : reference(run.probes.size()), distance(run.probes.size())
{
  for (const auto &probe : run.probes) names.push_back(probe->name());
  const double tiny = 1e-9 * (run.time.size() > 1 ? run.time[1] - run.time[0] : 1.0);
  for (unsigned int r = 0; r < std::min(run.n_rows(), rigid.n_rows()) && std::abs(run.time[r] - rigid.time[r]) <= tiny; ++r)
    {
      time.push_back(run.time[r]);
      for (std::size_t p = 0; p < names.size(); ++p)
        {
          reference[p].push_back(rigid.positions[p][r]);
          distance[p].push_back((run.positions[p][r] - rigid.positions[p][r]).norm());
        }
    }
  for (std::size_t p = 0; p < names.size(); ++p)
    {
      Largest m{names[p], 0.0, time.empty() ? 0.0 : time.front()};
      for (std::size_t r = 0; r < time.size(); ++r)
        if (distance[p][r] > m.distance) m = {names[p], distance[p][r], time[r]};
      maxima.push_back(m);
    }
}

void PathDeviation::write(OutputFolder &out) const
{
  std::ostringstream csv;
  csv << "time_s";
  for (const auto &n : names) csv << "," << n << "_rigid_x_m," << n << "_rigid_y_m," << n << "_rigid_z_m," << n << "_deviation_m";
  csv << "\n";
  for (std::size_t r = 0; r < time.size(); ++r)
    {
      csv << csv_number(time[r]);
      for (std::size_t p = 0; p < names.size(); ++p)
        csv << "," << csv_number(reference[p][r][0]) << "," << csv_number(reference[p][r][1]) << ","
            << csv_number(reference[p][r][2]) << "," << csv_number(distance[p][r]);
      csv << "\n";
    }
  out.add_text("deviation.csv", csv.str());

  out.add_text("deviation.gp", deviation_plot_script(names));
}

std::string PathDeviation::json(const unsigned int indent) const
{
  std::string list = "[";
  for (const auto &m : maxima)
    {
      JsonObject j;
      j.add("probe", m.probe).add("max_deviation_m", m.distance).add("at_time_s", m.time);
      list += (list.size() > 1 ? ", " : "") + j.str(indent);
    }
  return list + "]";
}
} // namespace flextrack::io
