// Truncated Taylor series ("jets") for exact derivatives of curves.
//
// A Jet holds the normalised Taylor coefficients c[k] = f^(k)(x0) / k! of a function
// around x0, up to order 4. Arithmetic on jets is exact (no finite differences), so a curve
// written as an expression in its parameter yields its first four derivatives to rounding
// error. Four derivatives are what the exact curvature, torsion and their arc-length
// derivatives need (torsion' involves y'''').
//
// The order is a template parameter: a drive law needs its value and first derivative, and a
// curve's speed |y'(p)| (the arc-length quadrature's integrand, ten evaluations per Gauss rule)
// its first derivative only. Every operation computes coefficient k from coefficients 0..k alone,
// in the same order whatever the truncation, so a lower-order jet gives bit for bit the leading
// coefficients of a Jet, at a fraction of the cost (a product: 3 multiplications at order 1,
// 15 at order 4).
#pragma once

#include <array>
#include <cmath>

namespace flextrack::geometry
{
constexpr int jet_order = 4;

template <int N>
struct TaylorJet
{
  static_assert(N >= 1 && N <= 4, "derivatives up to the fourth");
  std::array<double, N + 1> c{};

  static TaylorJet constant(const double v) { TaylorJet j; j.c[0] = v; return j; }
  /// The independent variable x at x0: x0 + 1*h.
  static TaylorJet variable(const double x0) { TaylorJet j; j.c[0] = x0; j.c[1] = 1.0; return j; }

  double value() const { return c[0]; }
  /// k-th derivative f^(k)(x0), k <= N.
  double derivative(const int k) const
  {
    static constexpr double factorial[] = {1., 1., 2., 6., 24.};
    return c[k] * factorial[k];
  }
  /// True for the plain variable x0 + h: composing a jet with it changes nothing.
  bool is_variable() const
  {
    bool plain = c[1] == 1.0;
    for (int k = 2; k <= N; ++k) plain = plain && c[k] == 0.0;
    return plain;
  }
};

/// Value and four derivatives: curves (curvature, torsion and their rates).
using Jet = TaylorJet<jet_order>;
/// Value and first derivative.
using Dual = TaylorJet<1>;

template <int N>
inline TaylorJet<N> operator+(TaylorJet<N> a, const TaylorJet<N> &b) { for (int k = 0; k <= N; ++k) a.c[k] += b.c[k]; return a; }
template <int N>
inline TaylorJet<N> operator-(TaylorJet<N> a, const TaylorJet<N> &b) { for (int k = 0; k <= N; ++k) a.c[k] -= b.c[k]; return a; }
template <int N>
inline TaylorJet<N> operator-(TaylorJet<N> a) { for (auto &v : a.c) v = -v; return a; }
template <int N>
inline TaylorJet<N> operator*(const double s, TaylorJet<N> a) { for (auto &v : a.c) v *= s; return a; }

template <int N>
inline TaylorJet<N> operator*(const TaylorJet<N> &a, const TaylorJet<N> &b)
{
  TaylorJet<N> r;
  for (int k = 0; k <= N; ++k)
    for (int i = 0; i <= k; ++i)
      r.c[k] += a.c[i] * b.c[k - i];
  return r;
}

template <int N>
inline TaylorJet<N> operator/(const TaylorJet<N> &a, const TaylorJet<N> &b)
{
  TaylorJet<N> q;
  for (int k = 0; k <= N; ++k)
    {
      double v = a.c[k];
      for (int i = 1; i <= k; ++i)
        v -= b.c[i] * q.c[k - i];
      q.c[k] = v / b.c[0];
    }
  return q;
}

template <int N>
inline TaylorJet<N> exp(const TaylorJet<N> &a)
{
  TaylorJet<N> e;
  e.c[0] = std::exp(a.c[0]);
  for (int k = 1; k <= N; ++k)
    for (int i = 1; i <= k; ++i)
      e.c[k] += i * a.c[i] * e.c[k - i] / k;
  return e;
}

template <int N>
inline TaylorJet<N> log(const TaylorJet<N> &a)
{
  TaylorJet<N> l;
  l.c[0] = std::log(a.c[0]);
  for (int k = 1; k <= N; ++k)
    {
      double v = a.c[k];
      for (int i = 1; i < k; ++i)
        v -= i * l.c[i] * a.c[k - i] / k;
      l.c[k] = v / a.c[0];
    }
  return l;
}

/// sin and cos together (their recurrences are coupled); hyperbolic = true gives sinh, cosh.
template <int N>
inline void sin_cos(const TaylorJet<N> &a, TaylorJet<N> &s, TaylorJet<N> &co, const bool hyperbolic = false)
{
  s = TaylorJet<N>(); co = TaylorJet<N>();
  s.c[0]  = hyperbolic ? std::sinh(a.c[0]) : std::sin(a.c[0]);
  co.c[0] = hyperbolic ? std::cosh(a.c[0]) : std::cos(a.c[0]);
  const double sign = hyperbolic ? 1.0 : -1.0;
  for (int k = 1; k <= N; ++k)
    for (int i = 1; i <= k; ++i)
      {
        s.c[k]  += i * a.c[i] * co.c[k - i] / k;
        co.c[k] += sign * i * a.c[i] * s.c[k - i] / k;
      }
}

template <int N>
inline TaylorJet<N> sqrt(const TaylorJet<N> &a)
{
  TaylorJet<N> r;
  r.c[0] = std::sqrt(a.c[0]);
  for (int k = 1; k <= N; ++k)
    {
      double v = a.c[k];
      for (int i = 1; i < k; ++i)
        v -= r.c[i] * r.c[k - i];
      r.c[k] = v / (2.0 * r.c[0]);
    }
  return r;
}

/// a^p for a constant real exponent p (a(x0) > 0, or p a non-negative integer).
template <int N>
inline TaylorJet<N> pow(const TaylorJet<N> &a, const double p)
{
  if (p == std::floor(p) && std::abs(p) <= 64)
    {
      // Integer powers by repeated squaring: valid for negative bases too.
      TaylorJet<N> result = TaylorJet<N>::constant(1.0), base = a;
      for (long n = static_cast<long>(std::abs(p)); n > 0; n >>= 1)
        {
          if (n & 1) result = result * base;
          base = base * base;
        }
      return p >= 0 ? result : TaylorJet<N>::constant(1.0) / result;
    }
  TaylorJet<N> u;
  u.c[0] = std::pow(a.c[0], p);
  for (int k = 1; k <= N; ++k)
    {
      double v = 0;
      for (int i = 0; i < k; ++i)
        v += (p * (k - i) - i) * a.c[k - i] * u.c[i];
      u.c[k] = v / (k * a.c[0]);
    }
  return u;
}

/// atan via (1 + a^2) atan(a)' = a'.
template <int N>
inline TaylorJet<N> atan(const TaylorJet<N> &a)
{
  const TaylorJet<N> d = TaylorJet<N>::constant(1.0) + a * a;
  TaylorJet<N> r;
  r.c[0] = std::atan(a.c[0]);
  for (int k = 1; k <= N; ++k)
    {
      double v = k * a.c[k];
      for (int j = 1; j < k; ++j)
        v -= d.c[j] * (k - j) * r.c[k - j];
      r.c[k] = v / (k * d.c[0]);
    }
  return r;
}

/// Composition f(g) where f is a jet around g(x0) and g a jet around x0.
template <int N>
inline TaylorJet<N> compose(const TaylorJet<N> &f, TaylorJet<N> g)
{
  g.c[0] = 0.0;
  TaylorJet<N> result = TaylorJet<N>::constant(f.c[0]), power = TaylorJet<N>::constant(1.0);
  for (int k = 1; k <= N; ++k)
    {
      power = power * g;
      result = result + f.c[k] * power;
    }
  return result;
}

/// Series reversion: given g with g(x0) = y0 and g'(x0) != 0, the jet of g^{-1} around y0.
template <int N>
inline TaylorJet<N> invert(const TaylorJet<N> &g, const double x0)
{
  // h(d) solves g(x0 + h) = y0 + d. Fixed point h = (d - sum_{k>=2} g_k h^k) / g_1
  // gains one order per sweep.
  TaylorJet<N> d = TaylorJet<N>::variable(0.0), h;
  for (int sweep = 0; sweep < N; ++sweep)
    {
      TaylorJet<N> rest, power = h;
      for (int k = 2; k <= N; ++k)
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
