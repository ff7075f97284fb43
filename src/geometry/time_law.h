// A law of time from the scene (a driver s(t), a load F(t)) checked before a run (issue 23,
// items 5-7). Before this check such a law was first evaluated inside the integrator: log(t) or
// sqrt(-1) reached LAPACK as NaN ("gesdd returned -4", an internal error), 1/(t - 0.5) or a
// law of 1e308 ground on with ever smaller steps. Here the law, and for a driver its first two
// derivatives (the velocity and acceleration the constraint imposes), are evaluated at the start
// time and at 2001 points over the run; the run is refused, naming the time and the value, if
//  - a value is not finite (NaN, +-inf: log(0), sqrt(-1), exp(1000 t) overflowing),
//  - a value exceeds max_law_magnitude (1e15 SI units: no machine has such a force or drive,
//    and the integrator's error weights overflow on squares of such numbers), or
//  - the law has a pole between grid points: zooming in on the largest |value| keeps finding
//    values ten times larger at every level (a smooth law's maximum converges instead).
#pragma once

#include <geometry/expression.h>

namespace flextrack::geometry
{
/// Largest |value| of a law (and |derivative| times the run's span, to the power of its order)
/// accepted [SI units of the entry].
constexpr double max_law_magnitude = 1e15;

/// The time window of a run [s]; empty (end <= start): laws are not checked.
struct TimeWindow
{
  double start = 0, end = 0;
  bool empty() const { return !(end > start); }
};

/// Throws ExpressionError saying where @p law fails on @p window (see above). @p derivatives:
/// how many derivatives must be finite and bounded as well (0 for a load, 2 for a driver).
void check_time_law(const Expression &law, const TimeWindow &window, int derivatives);
} // namespace flextrack::geometry
