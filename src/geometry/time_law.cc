#include <geometry/time_law.h>

#include <base/text.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace flextrack::geometry
{
using base::number_text;

namespace
{
constexpr int grid_intervals = 2000;
constexpr int zoom_levels = 6, zoom_points = 50;

/// Which derivative of a law was the largest or not finite, and its value: put into words only
/// for a message (number_text for every one of the 2300 samples was most of the check's cost).
struct Derivative
{
  int order = 0;
  double value = 0;
  std::string text() const
  {
    static const char *names[] = {"value", "first derivative", "second derivative"};
    return std::string(names[order]) + " " + number_text(value);
  }
};

/// The largest of |f|, |f'| T and |f''| T^2 at @p t (the derivatives scaled by the span T to the
/// law's own unit), or NaN if any is not finite; @p what is the one that is largest or bad.
double size_at(const Expression &law, const double t, const double span, const int derivatives, Derivative &what)
{
  const Jet j = law.jet(t);
  double largest = 0;
  for (int k = 0; k <= derivatives; ++k)
    {
      const double d = j.derivative(k);
      if (!std::isfinite(d))
        {
          what = {k, d};
          return std::numeric_limits<double>::quiet_NaN();
        }
      const double scaled = std::abs(d) * std::pow(span, k);
      if (scaled >= largest)
        {
          largest = scaled;
          what = {k, d};
        }
    }
  return largest;
}
} // namespace

void check_time_law(const Expression &law, const TimeWindow &window, const int derivatives)
{
  if (window.empty()) return;
  const double t0 = window.start, span = window.end - window.start;
  const std::string text = "'" + law.text() + "'";
  std::vector<double> size(grid_intervals + 1);
  std::string too_large; // the first grid point beyond max_law_magnitude, reported if it is no pole
  for (int i = 0; i <= grid_intervals; ++i)
    {
      const double t = i == grid_intervals ? window.end : t0 + span * i / grid_intervals;
      Derivative what;
      size[i] = size_at(law, t, span, derivatives, what);
      if (std::isnan(size[i]))
        throw ExpressionError(text + " is not finite at t = " + number_text(t) + " s (" + what.text() +
                              "): a law of time must be defined over the whole run, from the start time to the end time");
      if (size[i] > max_law_magnitude && too_large.empty())
        too_large = text + " reaches " + what.text() + " at t = " + number_text(t) + " s: beyond " + number_text(max_law_magnitude) +
                    " (SI units; derivatives times the run's duration); no machine needs it";
    }
  // A pole between grid points: zoom in on the largest value.
  int k = std::max_element(size.begin(), size.end()) - size.begin();
  double a = t0 + span * std::max(k - 1, 0) / grid_intervals, b = t0 + span * std::min(k + 1, grid_intervals) / grid_intervals;
  double previous = size[k];
  int growing = 0;
  for (int level = 0; level < zoom_levels; ++level)
    {
      double best = -1, t_best = a;
      for (int i = 0; i <= zoom_points; ++i)
        {
          const double t = a + (b - a) * i / zoom_points;
          Derivative what;
          const double s = size_at(law, t, span, derivatives, what);
          if (std::isnan(s)) // the pole itself
            throw ExpressionError(text + " has a pole at t = " + number_text(t) + " s (" + what.text() +
                                  "): a law of time must be bounded over the whole run");
          if (s > best) best = s, t_best = t;
        }
      growing = best > 10 * previous ? growing + 1 : 0;
      previous = best;
      const double h = (b - a) / zoom_points;
      a = std::max(t0, t_best - h), b = std::min(window.end, t_best + h);
      if (growing >= 3)
        throw ExpressionError(text + " has a pole near t = " + number_text(t_best) + " s (it grows without bound: " +
                              number_text(best) + " within " + number_text(h) + " s of it): a law of time must be bounded over the whole run");
    }
  if (!too_large.empty()) throw ExpressionError(too_large);
}
} // namespace flextrack::geometry
