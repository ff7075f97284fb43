#include <reduction/plausibility.h>

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/lac/lapack_templates.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace flextrack::reduction
{
using namespace dealii;

namespace
{
std::string number(const double x)
{
  std::ostringstream s;
  s.precision(2);
  s << std::scientific << x;
  return s.str();
}

/// Eigenvalues, ascending, of the symmetric part (A + A^T) / 2 of the square matrix @p A
/// (LAPACK dsyev, about 4 n^3 / 3 flops: 0.01 s for n = 300).
std::vector<double> symmetric_part_eigenvalues(const FullMatrix<double> &A)
{
  const types::blas_int n = A.m();
  if (n == 0) return {};
  std::vector<double> a(n * n), w(n);
  for (types::blas_int i = 0; i < n; ++i)
    for (types::blas_int j = 0; j < n; ++j) a[i + n * j] = 0.5 * (A(i, j) + A(j, i));
  types::blas_int lwork = std::max<types::blas_int>(1, 3 * n - 1), info = 0;
  std::vector<double> work(lwork);
  syev("N", "U", &n, a.data(), &n, w.data(), work.data(), &lwork, &info);
  if (info != 0) throw std::runtime_error("the eigenvalues of a reduced matrix did not converge (LAPACK dsyev)");
  return w;
}

void require_symmetric(const FullMatrix<double> &A, const std::string &what, const std::string &unit)
{
  double largest = 0;
  for (unsigned int i = 0; i < A.m(); ++i)
    for (unsigned int j = 0; j < A.n(); ++j) largest = std::max(largest, std::abs(A(i, j)));
  for (unsigned int i = 0; i < A.m(); ++i)
    for (unsigned int j = i + 1; j < A.n(); ++j)
      if (std::abs(A(i, j) - A(j, i)) > symmetry_tolerance * largest)
        throw std::runtime_error(what + " is not symmetric: [" + std::to_string(i) + "," + std::to_string(j) +
                                 "] = " + number(A(i, j)) + " " + unit + " but [" + std::to_string(j) + "," +
                                 std::to_string(i) + "] = " + number(A(j, i)) + " " + unit + " (allowed: " +
                                 number(symmetry_tolerance) + " of the largest entry, " + number(largest) + " " + unit + ")");
}

/// Smallest eigenvalue >= -semidefinite_tolerance * largest eigenvalue magnitude.
void require_semidefinite(const std::vector<double> &eigenvalues, const std::string &what, const std::string &unit)
{
  if (eigenvalues.empty()) return;
  const double scale = std::max(std::abs(eigenvalues.front()), std::abs(eigenvalues.back()));
  if (eigenvalues.front() < -semidefinite_tolerance * scale)
    throw std::runtime_error(what + " is not positive semi-definite (smallest eigenvalue " + number(eigenvalues.front()) +
                             " " + unit + ", largest " + number(eigenvalues.back()) + " " + unit + ")");
}

void check_reduced_matrices(const ReducedBody &body)
{
  const std::string M = "the reduced mass matrix (/reduced/mass)", K = "the reduced stiffness matrix (/reduced/stiffness)";
  require_symmetric(body.mass, M, "kg");
  const auto m = symmetric_part_eigenvalues(body.mass);
  if (!m.empty() && !(m.front() > definite_tolerance * m.back()))
    throw std::runtime_error(M + " is not positive definite (smallest eigenvalue " + number(m.front()) + " kg, largest " +
                             number(m.back()) + " kg)");
  require_symmetric(body.stiffness, K, "N/m");
  require_semidefinite(symmetric_part_eigenvalues(body.stiffness), K, "N/m");
  // Only the symmetric part dissipates (power eta_dot^T C eta_dot); no symmetry is required.
  require_semidefinite(symmetric_part_eigenvalues(body.damping),
                       "the symmetric part of the reduced damping matrix (/reduced/damping)", "N s/m");
  // A frequency is the signed square root of an eigenvalue of K over 2 pi: a zero eigenvalue
  // (a rigid-body motion or mechanism the supports leave free) that round-off made negative gives
  // a small negative frequency. Allowed as far as K's eigenvalues are: (2 pi f)^2 down to
  // -semidefinite_tolerance (2 pi f_max)^2, i.e. f >= -1e-4 f_max.
  double f_max = 0;
  for (const double f : body.frequencies_hz) f_max = std::max(f_max, std::abs(f));
  for (unsigned int k = 0; k < body.frequencies_hz.size(); ++k)
    if (!(body.frequencies_hz[k] >= -std::sqrt(semidefinite_tolerance) * f_max))
      throw std::runtime_error("frequency " + std::to_string(k) + " (/reduced/frequencies_hz) is negative (" +
                               number(body.frequencies_hz[k]) + " Hz; allowed down to -" +
                               number(std::sqrt(semidefinite_tolerance)) + " of the largest, " + number(f_max) +
                               " Hz)");
}

/// Principal moments of @p J, ascending.
std::array<double, 3> principal_moments(const Tensor<2, 3> &J)
{
  const auto e = eigenvalues(symmetrize(J)); // descending
  return {{e[2], e[1], e[0]}};
}

/// J1 + J2 >= J3 within round-off, @p scale [kg m^2] setting its size.
void require_triangle_inequality(const std::array<double, 3> &J, const std::string &what, const double scale)
{
  if (J[0] + J[1] < J[2] - semidefinite_tolerance * scale)
    throw std::runtime_error(what + " has principal moments " + number(J[0]) + ", " + number(J[1]) + ", " + number(J[2]) +
                             " kg m^2 that violate the triangle inequality J1 + J2 >= J3");
}

void check_inertia(const InertiaInvariants &inv)
{
  if (!(inv.mass > 0))
    throw std::runtime_error("the mass (/inertia/mass) is not positive (" + number(inv.mass) + " kg)");
  const std::string origin = "the inertia tensor about the origin (/inertia/inertia_origin)";
  FullMatrix<double> J(3, 3);
  for (unsigned int i = 0; i < 3; ++i)
    for (unsigned int j = 0; j < 3; ++j) J(i, j) = inv.inertia_origin[i][j];
  require_symmetric(J, origin, "kg m^2");
  const auto moments = principal_moments(inv.inertia_origin);
  if (!(moments[0] > 0))
    throw std::runtime_error(origin + " has a principal moment that is not positive (" + number(moments[0]) + " kg m^2)");
  const double scale = moments[2];
  require_triangle_inequality(moments, origin, scale);
  // About the centre of mass: J_c = J_O - m (|c|^2 1 - c c^T), c = s / m. Cancellation leaves
  // round-off relative to J_O (whose largest moment bounds m |c|^2), hence the same scale.
  const std::string centre = "the inertia tensor about the centre of mass (from /inertia/mass, first_moment and "
                             "inertia_origin)";
  const auto central = principal_moments(inv.inertia_about_centre_of_mass());
  if (central[0] < -semidefinite_tolerance * scale)
    throw std::runtime_error(centre + " is not positive semi-definite (smallest principal moment " + number(central[0]) +
                             " kg m^2): the first moment does not belong to this mass and inertia");
  require_triangle_inequality(central, centre, scale);
}
} // namespace

void check_physical_plausibility(const ReducedBody &body)
{
  check_inertia(body.invariants);
  check_reduced_matrices(body);
}
} // namespace flextrack::reduction
