// Truncated Taylor series ("jets") for exact derivatives of curves.
//
// A Jet holds the normalised Taylor coefficients c[k] = f^(k)(x0) / k! of a function
// around x0, up to order 4. Arithmetic on jets is exact (no finite differences), so a curve
// written as an expression in its parameter yields its first four derivatives to rounding
// error. Four derivatives are what the exact curvature, torsion and their arc-length
// derivatives need (torsion' involves y'''').
#pragma once

#include <array>
#include <cmath>

namespace flextrack::geometry
{
constexpr int jet_order = 4;

struct Jet
{
  std::array<double, jet_order + 1> c{};

  static Jet constant(const double v) { Jet j; j.c[0] = v; return j; }
  /// The independent variable x at x0: x0 + 1*h.
  static Jet variable(const double x0) { Jet j; j.c[0] = x0; j.c[1] = 1.0; return j; }

  double value() const { return c[0]; }
  /// k-th derivative f^(k)(x0).
  double derivative(const int k) const
  {
    static constexpr double factorial[] = {1., 1., 2., 6., 24.};
    return c[k] * factorial[k];
  }
};

inline Jet operator+(Jet a, const Jet &b) { for (int k = 0; k <= jet_order; ++k) a.c[k] += b.c[k]; return a; }
inline Jet operator-(Jet a, const Jet &b) { for (int k = 0; k <= jet_order; ++k) a.c[k] -= b.c[k]; return a; }
inline Jet operator-(Jet a) { for (auto &v : a.c) v = -v; return a; }
inline Jet operator*(const double s, Jet a) { for (auto &v : a.c) v *= s; return a; }

inline Jet operator*(const Jet &a, const Jet &b)
{
  Jet r;
  for (int k = 0; k <= jet_order; ++k)
    for (int i = 0; i <= k; ++i)
      r.c[k] += a.c[i] * b.c[k - i];
  return r;
}

inline Jet operator/(const Jet &a, const Jet &b)
{
  Jet q;
  for (int k = 0; k <= jet_order; ++k)
    {
      double v = a.c[k];
      for (int i = 1; i <= k; ++i)
        v -= b.c[i] * q.c[k - i];
      q.c[k] = v / b.c[0];
    }
  return q;
}

inline Jet exp(const Jet &a)
{
  Jet e;
  e.c[0] = std::exp(a.c[0]);
  for (int k = 1; k <= jet_order; ++k)
    for (int i = 1; i <= k; ++i)
      e.c[k] += i * a.c[i] * e.c[k - i] / k;
  return e;
}

inline Jet log(const Jet &a)
{
  Jet l;
  l.c[0] = std::log(a.c[0]);
  for (int k = 1; k <= jet_order; ++k)
    {
      double v = a.c[k];
      for (int i = 1; i < k; ++i)
        v -= i * l.c[i] * a.c[k - i] / k;
      l.c[k] = v / a.c[0];
    }
  return l;
}

/// sin and cos together (their recurrences are coupled); hyperbolic = true gives sinh, cosh.
inline void sin_cos(const Jet &a, Jet &s, Jet &co, const bool hyperbolic = false)
{
  s = Jet(); co = Jet();
  s.c[0]  = hyperbolic ? std::sinh(a.c[0]) : std::sin(a.c[0]);
  co.c[0] = hyperbolic ? std::cosh(a.c[0]) : std::cos(a.c[0]);
  const double sign = hyperbolic ? 1.0 : -1.0;
  for (int k = 1; k <= jet_order; ++k)
    for (int i = 1; i <= k; ++i)
      {
        s.c[k]  += i * a.c[i] * co.c[k - i] / k;
        co.c[k] += sign * i * a.c[i] * s.c[k - i] / k;
      }
}

inline Jet sqrt(const Jet &a)
{
  Jet r;
  r.c[0] = std::sqrt(a.c[0]);
  for (int k = 1; k <= jet_order; ++k)
    {
      double v = a.c[k];
      for (int i = 1; i < k; ++i)
        v -= r.c[i] * r.c[k - i];
      r.c[k] = v / (2.0 * r.c[0]);
    }
  return r;
}

/// a^p for a constant real exponent p (a(x0) > 0, or p a non-negative integer).
inline Jet pow(const Jet &a, const double p)
{
  if (p == std::floor(p) && std::abs(p) <= 64)
    {
      // Integer powers by repeated squaring: valid for negative bases too.
      Jet result = Jet::constant(1.0), base = a;
      for (long n = static_cast<long>(std::abs(p)); n > 0; n >>= 1)
        {
          if (n & 1) result = result * base;
          base = base * base;
        }
      return p >= 0 ? result : Jet::constant(1.0) / result;
    }
  Jet u;
  u.c[0] = std::pow(a.c[0], p);
  for (int k = 1; k <= jet_order; ++k)
    {
      double v = 0;
      for (int i = 0; i < k; ++i)
        v += (p * (k - i) - i) * a.c[k - i] * u.c[i];
      u.c[k] = v / (k * a.c[0]);
    }
  return u;
}

/// atan via (1 + a^2) atan(a)' = a'.
inline Jet atan(const Jet &a)
{
  const Jet d = Jet::constant(1.0) + a * a;
  Jet r;
  r.c[0] = std::atan(a.c[0]);
  for (int k = 1; k <= jet_order; ++k)
    {
      double v = k * a.c[k];
      for (int j = 1; j < k; ++j)
        v -= d.c[j] * (k - j) * r.c[k - j];
      r.c[k] = v / (k * d.c[0]);
    }
  return r;
}

/// Composition f(g) where f is a jet around g(x0) and g a jet around x0.
inline Jet compose(const Jet &f, Jet g)
{
  g.c[0] = 0.0;
  Jet result = Jet::constant(f.c[0]), power = Jet::constant(1.0);
  for (int k = 1; k <= jet_order; ++k)
    {
      power = power * g;
      result = result + f.c[k] * power;
    }
  return result;
}

/// Series reversion: given g with g(x0) = y0 and g'(x0) != 0, the jet of g^{-1} around y0.
inline Jet invert(const Jet &g, const double x0)
{
  // h(d) solves g(x0 + h) = y0 + d. Fixed point h = (d - sum_{k>=2} g_k h^k) / g_1
  // gains one order per sweep.
  Jet d = Jet::variable(0.0), h;
  for (int sweep = 0; sweep < jet_order; ++sweep)
    {
      Jet rest, power = h;
      for (int k = 2; k <= jet_order; ++k)
        {
          power = power * h;
          rest = rest + g.c[k] * power;
        }
      h = (1.0 / g.c[1]) * (d - rest);
    }
  h.c[0] = x0;
  return h;
}

/// A point of a curve with its derivatives: y[k] holds the Taylor coefficients of component k.
using Jet3 = std::array<Jet, 3>;
} // namespace flextrack::geometry
