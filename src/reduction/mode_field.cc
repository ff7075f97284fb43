#include <reduction/mode_field.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace flextrack::reduction
{
namespace
{
/// Lagrange basis values and derivatives on the nodes xi at x.
void lagrange(const std::vector<double> &xi, const double x, double *N, double *dN)
{
  const unsigned int n = xi.size();
  for (unsigned int j = 0; j < n; ++j)
    {
      double value = 1, derivative = 0;
      for (unsigned int m = 0; m < n; ++m)
        {
          if (m == j) continue;
          const double inv = 1.0 / (xi[j] - xi[m]);
          derivative = derivative * (x - xi[m]) * inv + value * inv;
          value *= (x - xi[m]) * inv;
        }
      N[j] = value;
      dN[j] = derivative;
    }
}
} // namespace

ArmModeField::ArmModeField(ArmModeData data, const Interpolation interpolation_)
  : d(std::move(data)), interpolation(interpolation_), p(d.xi.size() - 1)
{
  // Vertex slopes: the mean of the FE slopes of the cells on either side.
  const unsigned int n = d.n_modes * 6, cells = d.n_cells();
  vertex_slope.assign((cells + 1) * n, 0.0);
  end_slope.assign(cells * 2 * n, 0.0);
  std::vector<double> value(n);
  for (unsigned int c = 0; c < cells; ++c)
    for (unsigned int end = 0; end < 2; ++end)
      {
        double *slope = &end_slope[(2 * c + end) * n];
        fe_evaluate(c, end, value.data(), slope);
        const unsigned int v = c + end;
        const double weight = (v == 0 || v == cells) ? 1.0 : 0.5;
        for (unsigned int i = 0; i < n; ++i) vertex_slope[v * n + i] += weight * slope[i];
      }
}

std::pair<unsigned int, double> ArmModeField::locate(const double s) const
{
  const double L = d.length();
  if (!(s >= 0 && s <= L))
    {
      std::ostringstream m;
      m << "arc length s = " << s << " m is off arm '" << d.name << "' (0 <= s <= " << L << " m)";
      throw std::out_of_range(m.str());
    }
  const auto it = std::upper_bound(d.cell_s.begin() + 1, d.cell_s.end() - 1, s);
  const unsigned int c = it - d.cell_s.begin() - 1;
  return {c, (s - d.cell_s[c]) / (d.cell_s[c + 1] - d.cell_s[c])};
}

void ArmModeField::fe_evaluate(const unsigned int cell, const double x, double *value, double *slope) const
{
  const unsigned int n = d.n_modes * 6;
  double N[8], dN[8];
  lagrange(d.xi, x, N, dN);
  const double h = d.cell_s[cell + 1] - d.cell_s[cell];
  std::fill(value, value + n, 0.0);
  std::fill(slope, slope + n, 0.0);
  for (unsigned int j = 0; j <= p; ++j)
    {
      const double *v = &d.values[(cell * (p + 1) + j) * n];
      const double dj = dN[j] / h;
      for (unsigned int i = 0; i < n; ++i)
        {
          value[i] += N[j] * v[i];
          slope[i] += dj * v[i];
        }
    }
}

void ArmModeField::evaluate(const double s, double *value, double *slope) const
{
  const auto [c, x] = locate(s);
  if (interpolation == Interpolation::finite_element) return fe_evaluate(c, x, value, slope);
  // FE field plus the blend corrections at both ends (header comment).
  fe_evaluate(c, x, value, slope);
  const unsigned int n = d.n_modes * 6;
  const double h = d.cell_s[c + 1] - d.cell_s[c];
  const auto psi = [](const double t, double &v, double &dv) { // psi(t), psi'(t) (per unit t)
    if (t >= blend)
      v = dv = 0;
    else
      {
        const double r = 1 - t / blend;
        v = t * r * r;
        dv = r * (1 - 3 * t / blend);
      }
  };
  double p0, dp0, p1, dp1;
  psi(x, p0, dp0);
  psi(1 - x, p1, dp1);
  if (p0 == 0 && dp0 == 0 && p1 == 0 && dp1 == 0) return;
  const double *m0 = &vertex_slope[c * n], *m1 = &vertex_slope[(c + 1) * n];
  const double *e0 = &end_slope[2 * c * n], *e1 = &end_slope[(2 * c + 1) * n];
  for (unsigned int i = 0; i < n; ++i)
    {
      const double a = m0[i] - e0[i], b = m1[i] - e1[i];
      value[i] += h * (p0 * a - p1 * b);
      slope[i] += dp0 * a + dp1 * b;
    }
}
} // namespace flextrack::reduction
