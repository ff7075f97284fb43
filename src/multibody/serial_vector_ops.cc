// Compiled vector operations for SUNDIALS' serial N_Vector (serial_vector_ops.h).
#include <multibody/serial_vector_ops.h>

#include <nvector/nvector_serial.h>

#include <cmath>

namespace flextrack::multibody
{
namespace
{
using Index = sunindextype;

double *data(N_Vector v) { return NV_DATA_S(v); }
Index length(N_Vector v) { return NV_LENGTH_S(v); }

// The root of a sum of squares, 0 for a sum that is not positive (SUNDIALS' SUNRsqrt).
double root(const double s) { return s <= 0 ? 0 : std::sqrt(s); }

/// z = a x + b y, with SUNDIALS' forms of the sum for coefficients of 1, -1 and equal or
/// opposite coefficients (y + a x, y - x, a (x + y), b y - x, ...): they differ from a x + b y
/// only in rounding and in the sign of a zero result, and keep every result equal to the
/// library's to the last bit.
void linear_sum(const double a, N_Vector x, const double b, N_Vector y, N_Vector z)
{
  const double *xd = data(x), *yd = data(y);
  double *zd = data(z);
  const Index n = length(x);
  const auto each = [&](auto &&f) {
    for (Index i = 0; i < n; ++i) zd[i] = f(xd[i], yd[i]);
  };
  if (b == 1 && z == y) // y += a x
    {
      if (a == 1) each([](double u, double w) { return w + u; });
      else if (a == -1) each([](double u, double w) { return w - u; });
      else each([a](double u, double w) { return w + a * u; });
    }
  else if (a == 1 && z == x) // x += b y
    {
      if (b == 1) each([](double u, double w) { return u + w; });
      else if (b == -1) each([](double u, double w) { return u - w; });
      else each([b](double u, double w) { return u + b * w; });
    }
  else if (a == 1 && b == 1) each([](double u, double w) { return u + w; });
  else if (a == 1 && b == -1) each([](double u, double w) { return u - w; });
  else if (a == -1 && b == 1) each([](double u, double w) { return w - u; });
  else if (a == 1) each([b](double u, double w) { return b * w + u; });
  else if (b == 1) each([a](double u, double w) { return a * u + w; });
  else if (a == -1) each([b](double u, double w) { return b * w - u; });
  else if (b == -1) each([a](double u, double w) { return a * u - w; });
  else if (a == b) each([a](double u, double w) { return a * (u + w); });
  else if (a == -b) each([a](double u, double w) { return a * (u - w); });
  else each([a, b](double u, double w) { return a * u + b * w; });
}

void constant(const double c, N_Vector z)
{
  double *zd = data(z);
  for (Index i = 0, n = length(z); i < n; ++i) zd[i] = c;
}

void product(N_Vector x, N_Vector y, N_Vector z)
{
  const double *xd = data(x), *yd = data(y);
  double *zd = data(z);
  for (Index i = 0, n = length(x); i < n; ++i) zd[i] = xd[i] * yd[i];
}

void quotient(N_Vector x, N_Vector y, N_Vector z)
{
  const double *xd = data(x), *yd = data(y);
  double *zd = data(z);
  for (Index i = 0, n = length(x); i < n; ++i) zd[i] = xd[i] / yd[i];
}

void scale(const double c, N_Vector x, N_Vector z)
{
  const double *xd = data(x);
  double *zd = data(z);
  for (Index i = 0, n = length(x); i < n; ++i) zd[i] = c * xd[i];
}

void absolute(N_Vector x, N_Vector z)
{
  const double *xd = data(x);
  double *zd = data(z);
  for (Index i = 0, n = length(x); i < n; ++i) zd[i] = std::abs(xd[i]);
}

void inverse(N_Vector x, N_Vector z)
{
  const double *xd = data(x);
  double *zd = data(z);
  for (Index i = 0, n = length(x); i < n; ++i) zd[i] = 1.0 / xd[i];
}

void add_constant(N_Vector x, const double b, N_Vector z)
{
  const double *xd = data(x);
  double *zd = data(z);
  for (Index i = 0, n = length(x); i < n; ++i) zd[i] = xd[i] + b;
}

// The reductions add in index order, one term at a time (no reassociation: the sums equal the
// library's).
double dot_product(N_Vector x, N_Vector y)
{
  const double *xd = data(x), *yd = data(y);
  double s = 0;
  for (Index i = 0, n = length(x); i < n; ++i) s += xd[i] * yd[i];
  return s;
}

double max_norm(N_Vector x)
{
  const double *xd = data(x);
  double m = 0;
  for (Index i = 0, n = length(x); i < n; ++i)
    if (std::abs(xd[i]) > m) m = std::abs(xd[i]);
  return m;
}

double weighted_square_sum(N_Vector x, N_Vector w)
{
  const double *xd = data(x), *wd = data(w);
  double s = 0;
  for (Index i = 0, n = length(x); i < n; ++i)
    {
      const double p = xd[i] * wd[i];
      s += p * p;
    }
  return s;
}

/// Over the entries whose mask entry is positive only.
double weighted_square_sum_masked(N_Vector x, N_Vector w, N_Vector mask)
{
  const double *xd = data(x), *wd = data(w), *md = data(mask);
  double s = 0;
  for (Index i = 0, n = length(x); i < n; ++i)
    if (md[i] > 0)
      {
        const double p = xd[i] * wd[i];
        s += p * p;
      }
  return s;
}

double wrms_norm(N_Vector x, N_Vector w) { return root(weighted_square_sum(x, w) / length(x)); }

double wrms_norm_masked(N_Vector x, N_Vector w, N_Vector mask)
{
  return root(weighted_square_sum_masked(x, w, mask) / length(x));
}

double weighted_l2_norm(N_Vector x, N_Vector w) { return root(weighted_square_sum(x, w)); }

double minimum(N_Vector x)
{
  const double *xd = data(x);
  double m = xd[0];
  for (Index i = 1, n = length(x); i < n; ++i)
    if (xd[i] < m) m = xd[i];
  return m;
}

double l1_norm(N_Vector x)
{
  const double *xd = data(x);
  double s = 0;
  for (Index i = 0, n = length(x); i < n; ++i) s += std::abs(xd[i]);
  return s;
}

/// z_i = 1 where |x_i| >= c, else 0.
void compare(const double c, N_Vector x, N_Vector z)
{
  const double *xd = data(x);
  double *zd = data(z);
  for (Index i = 0, n = length(x); i < n; ++i) zd[i] = std::abs(xd[i]) >= c ? 1.0 : 0.0;
}

} // namespace

void install_compiled_ops(N_Vector v)
{
  if (N_VGetVectorID(v) != SUNDIALS_NVEC_SERIAL) return;
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = linear_sum;
  ops->nvconst = constant;
  ops->nvprod = product;
  ops->nvdiv = quotient;
  ops->nvscale = scale;
  ops->nvabs = absolute;
  ops->nvinv = inverse;
  ops->nvaddconst = add_constant;
  ops->nvdotprod = dot_product;
  ops->nvmaxnorm = max_norm;
  ops->nvwrmsnorm = wrms_norm;
  ops->nvwrmsnormmask = wrms_norm_masked;
  ops->nvmin = minimum;
  ops->nvwl2norm = weighted_l2_norm;
  ops->nvl1norm = l1_norm;
  ops->nvcompare = compare;
  // The fused and vector-array operations stay off: SUNDIALS' fallbacks loop over the operations
  // above. The local reductions are the same sums (for a serial vector there is nothing to combine).
  ops->nvdotprodlocal = dot_product;
  ops->nvmaxnormlocal = max_norm;
  ops->nvminlocal = minimum;
  ops->nvl1normlocal = l1_norm;
  ops->nvwsqrsumlocal = weighted_square_sum;
  ops->nvwsqrsummasklocal = weighted_square_sum_masked;
}
} // namespace flextrack::multibody
