// Runs that leave what their model can hold (growth_watch.h).
#include <base/text.h>
#include <multibody/body.h>
#include <multibody/growth_watch.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flextrack::multibody
{
namespace
{
const FloatingBody *flexible(const System &system, const unsigned int b)
{
  const auto *body = dynamic_cast<const FloatingBody *>(&system.body(b));
  return body && body->reduced_body() ? body : nullptr;
}

/// Elastic translation of interface-like point @p p (6 x n modes) at modal coordinates @p eta.
dealii::Tensor<1, 3> translation(const reduction::ReducedBody::Interface &p, const double *eta, const unsigned int n)
{
  dealii::Tensor<1, 3> u;
  for (unsigned int d = 0; d < 3; ++d)
    for (unsigned int k = 0; k < n; ++k) u[d] += p.modes(d, k) * eta[k];
  return u;
}
} // namespace

GrowthWatch::GrowthWatch(const System &system_) : system(system_)
{
  for (unsigned int b = 0; b < system.n_bodies(); ++b)
    if (const auto *body = flexible(system, b))
      {
        const auto &reduced = *body->reduced_body();
        dealii::Point<3> low, high;
        bool first = true;
        const auto extend = [&](const dealii::Point<3> &p) {
          for (unsigned int d = 0; d < 3; ++d)
            {
              low[d] = first ? p[d] : std::min(low[d], p[d]);
              high[d] = first ? p[d] : std::max(high[d], p[d]);
            }
          first = false;
        };
        for (const auto &p : reduced.points) extend(p);
        for (const auto &p : reduced.interfaces) extend(p.position);
        for (const auto &p : reduced.output_points) extend(p.position);
        const double size = first ? 0.0 : (high - low).norm();
        if (size <= 0) continue;
        const unsigned int n = body->n_modes();
        std::vector<double> extent(n, 0.0);
        const std::size_t P = reduced.points.size();
        if (reduced.point_modes.size() == 3 * n * P)
          for (unsigned int k = 0; k < n; ++k)
            for (std::size_t i = 0; i < P; ++i)
              {
                const double *u = &reduced.point_modes[(k * P + i) * 3];
                extent[k] = std::max(extent[k], std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
              }
        for (const auto *points : {&reduced.interfaces, &reduced.output_points})
          for (const auto &p : *points)
            for (unsigned int k = 0; k < n; ++k)
              extent[k] = std::max(extent[k], std::sqrt(p.modes(0, k) * p.modes(0, k) + p.modes(1, k) * p.modes(1, k) +
                                                        p.modes(2, k) * p.modes(2, k)));
        watched.push_back({b, size, std::move(extent)});
      }
}

double GrowthWatch::largest_displacement(const unsigned int b, const dealii::Vector<double> &y, dealii::Point<3> *where) const
{
  const auto *body = flexible(system, b);
  if (!body) return 0;
  const auto &reduced = *body->reduced_body();
  const unsigned int n = body->n_modes();
  const double *eta = system.q_of(b, y) + 7; // q_b = (R [3], p [4], eta [n])
  double largest = 0;
  const auto consider = [&](const dealii::Tensor<1, 3> &u, const dealii::Point<3> &at) {
    const double size = u.norm();
    if (!(size <= largest)) // NaN counts as the largest
      {
        largest = size;
        if (where) *where = at;
      }
  };
  const std::size_t P = reduced.points.size();
  if (reduced.point_modes.size() == 3 * n * P)
    for (std::size_t i = 0; i < P; ++i)
      {
        dealii::Tensor<1, 3> u;
        for (unsigned int k = 0; k < n; ++k)
          for (unsigned int d = 0; d < 3; ++d) u[d] += reduced.point_modes[(k * P + i) * 3 + d] * eta[k];
        consider(u, reduced.points[i]);
      }
  for (const auto &p : reduced.interfaces) consider(translation(p, eta, n), p.position);
  for (const auto &p : reduced.output_points) consider(translation(p, eta, n), p.position);
  return largest;
}

std::string GrowthWatch::check(const double t, const dealii::Vector<double> &y) const
{
  for (const auto &w : watched)
    {
      const double *eta = system.q_of(w.body, y) + 7;
      double bound = 0;
      for (unsigned int k = 0; k < w.mode_extent.size(); ++k) bound += w.mode_extent[k] * std::abs(eta[k]);
      if (bound <= size_fraction * w.size) continue; // NaN falls through to the scan
      dealii::Point<3> where;
      const double u = largest_displacement(w.body, y, &where);
      if (u <= size_fraction * w.size) continue;
      const auto &body = dynamic_cast<const FloatingBody &>(system.body(w.body));
      using base::number_text;
      std::ostringstream s;
      s << "the run stopped at t = " << number_text(t) << " s: the elastic displacement of body '" << body.name()
        << "' grew to " << number_text(u) << " m (at its point " << number_text(where[0]) << ", "
        << number_text(where[1]) << ", " << number_text(where[2]) << " m of the body frame), more than the body's size "
        << number_text(w.size) << " m: a reduced (linear) flexible body cannot hold that, the motion has become "
           "unstable or the body is loaded far beyond what it can carry. What to change: ";
      if (!body.geometric_stiffening())
        s << "'Geometric stiffening = false' on this body: a body that spins or carries axial load softens and "
             "buckles without it; set it true (the reduced body must hold geometric stiffness: 'Geometric "
             "stiffness = true' in its Reduction section), or check the loads and drivers";
      else
        s << "check the loads and drivers acting on it (a resonance without damping, a driver faster than the body "
             "can follow), or give its modes damping";
      return s.str();
    }
  return "";
}
} // namespace flextrack::multibody
