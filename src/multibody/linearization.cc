// Linearisation about a state and the eigenvalues of the constrained system (linearization.h).
#include <multibody/initial_conditions.h>
#include <multibody/linearization.h>
#include <multibody/static_stiffness.h>

#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/lapack_templates.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

FullMatrix<double> constraint_null_space(const FullMatrix<double> &B, const unsigned int n)
{
  if (B.m() == 0)
    {
      FullMatrix<double> N(n, n);
      for (unsigned int i = 0; i < n; ++i) N(i, i) = 1;
      return N;
    }
  // Right singular vectors of the singular values ~0 (B padded to n x n so that V is complete).
  LAPACKFullMatrix<double> Bl(n, n);
  for (unsigned int i = 0; i < B.m(); ++i)
    for (unsigned int k = 0; k < n; ++k) Bl(i, k) = B(i, k);
  Bl.compute_svd();
  const double largest = Bl.singular_value(0);
  const LAPACKFullMatrix<double> &Vt = Bl.get_svd_vt();
  std::vector<unsigned int> free;
  for (unsigned int i = 0; i < n; ++i)
    if (Bl.singular_value(i) <= 1e-10 * largest) free.push_back(i);
  FullMatrix<double> N(n, free.size());
  for (unsigned int c = 0; c < free.size(); ++c)
    for (unsigned int i = 0; i < n; ++i) N(i, c) = Vt(free[c], i);
  return N;
}
std::vector<LinearMode> linearize(System &system, const double t, const Vector<double> &y_in)
{
  const unsigned int nv = system.n_v();
  Vector<double> y(y_in), yp;
  consistent_derivatives(system, t, y, yp);

  FullMatrix<double> K(nv, nv), C(nv, nv), M, B;
  Vector<double> phi, phi_t;
  system.mass_matrix(y, M);
  system.constraints(t, y, false, phi, B, phi_t);
  // K = dR/dx and C = dR/dv: the velocity rows of the DAE Jacobian at (y, y'), which holds
  // v'0 and lambda0 (analytic bodies, joints and forces: System::assemble_jacobian).
  velocity_row_tangents(system, t, y, yp, K, &C);
  const FullMatrix<double> N = constraint_null_space(B, nv);
  const unsigned int nf = N.n();
  if (nf == 0) return {};
  FullMatrix<double> Mr(nf, nf), Kr(nf, nf), Cr(nf, nf);
  Mr.triple_product(M, N, N, true, false);
  Kr.triple_product(K, N, N, true, false);
  Cr.triple_product(C, N, N, true, false);

  // First-order form [0 I; -Mr^-1 Kr  -Mr^-1 Cr]
  LAPACKFullMatrix<double> Minv(nf);
  Minv = Mr;
  Minv.invert();
  FullMatrix<double> Mi(nf, nf), MK(nf, nf), MC(nf, nf);
  for (unsigned int i = 0; i < nf; ++i)
    for (unsigned int k = 0; k < nf; ++k) Mi(i, k) = Minv(i, k);
  Mi.mmult(MK, Kr);
  Mi.mmult(MC, Cr);
  // Eigenvalues and right eigenvectors of A (column-major for LAPACK's dgeev).
  const types::blas_int n2 = 2 * nf;
  std::vector<double> A(n2 * n2), wr(n2), wi(n2), vr(n2 * n2), vl(1);
  for (unsigned int i = 0; i < nf; ++i)
    {
      A[(nf + i) * n2 + i] = 1;
      for (unsigned int k = 0; k < nf; ++k)
        {
          A[k * n2 + nf + i] = -MK(i, k);
          A[(nf + k) * n2 + nf + i] = -MC(i, k);
        }
    }
  types::blas_int info = 0, lwork = -1, one = 1;
  double work_size = 0;
  geev("N", "V", &n2, A.data(), &n2, wr.data(), wi.data(), vl.data(), &one, vr.data(), &n2, &work_size, &lwork, &info);
  lwork = static_cast<types::blas_int>(work_size);
  std::vector<double> work(lwork);
  geev("N", "V", &n2, A.data(), &n2, wr.data(), wi.data(), vl.data(), &one, vr.data(), &n2, work.data(), &lwork, &info);
  AssertThrow(info == 0, ExcMessage("LAPACK dgeev failed in linearize() (info " + std::to_string(info) + ")"));

  std::vector<LinearMode> modes;
  for (unsigned int i = 0; i < unsigned(n2); ++i)
    {
      const std::complex<double> s(wr[i], wi[i]);
      if (s.imag() < 0) continue; // one of each conjugate pair
      LinearMode m;
      m.eigenvalue = s;
      m.frequency_hz = std::abs(s.imag()) / (2 * M_PI);
      m.damping_ratio = std::abs(s) > 0 ? -s.real() / std::abs(s) : 0.0;
      // dgeev: a complex pair (wi > 0 at i, < 0 at i + 1) has the vector vr(:, i) + i vr(:, i + 1).
      std::vector<std::complex<double>> z(nf);
      for (unsigned int k = 0; k < nf; ++k)
        z[k] = {vr[i * n2 + k], s.imag() > 0 ? vr[(i + 1) * n2 + k] : 0.0};
      m.shape.assign(nv, 0.0);
      double norm = 0;
      for (unsigned int r = 0; r < nv; ++r)
        {
          for (unsigned int k = 0; k < nf; ++k) m.shape[r] += N(r, k) * z[k];
          norm += std::norm(m.shape[r]);
        }
      if (norm > 0)
        for (auto &x : m.shape) x /= std::sqrt(norm);
      modes.push_back(std::move(m));
    }
  std::sort(modes.begin(), modes.end(), [](const LinearMode &a, const LinearMode &b) { return a.frequency_hz < b.frequency_hz; });
  return modes;
}

StabilityVerdict classify_stability(const std::vector<LinearMode> &modes)
{
  StabilityVerdict v;
  double largest = 1.0;
  for (const auto &m : modes) largest = std::max(largest, std::abs(m.eigenvalue));
  v.round_off = 1e-10 * largest;
  for (const auto &m : modes)
    {
      const bool grows = m.eigenvalue.real() > std::max(v.round_off, 1e-9 * std::abs(m.eigenvalue));
      v.grows.push_back(grows);
      if (!grows) continue;
      v.largest_growth_rate = v.unstable_modes ? std::max(v.largest_growth_rate, m.eigenvalue.real()) : m.eigenvalue.real();
      ++v.unstable_modes;
    }
  return v;
}

EquilibriumCheck check_equilibrium(const System &system, const double t, const Vector<double> &y, const Vector<double> &yp)
{
  const unsigned int nq = system.n_q(), nv = system.n_v(), nl = system.n_lambda();
  FullMatrix<double> M, B;
  Vector<double> Q, phi, phi_t, reaction(nv);
  system.mass_matrix(y, M);
  system.generalized_forces(t, y, Q);
  system.constraints(t, y, false, phi, B, phi_t);
  if (nl)
    {
      Vector<double> lambda(nl);
      for (unsigned int r = 0; r < nl; ++r) lambda[r] = y[nq + nv + r];
      B.Tvmult(reaction, lambda);
    }
  EquilibriumCheck c;
  double force_scale = 0, largest = -1;
  for (unsigned int i = 0; i < nv; ++i)
    {
      if (!(M(i, i) > 0)) continue; // a joint's own coordinate: no mass, v' does not appear
      const double w = std::sqrt(M(i, i));
      force_scale = std::max(force_scale, std::max(std::abs(Q[i]), std::abs(reaction[i])) / w);
      const double a = w * std::abs(yp[nq + i]);
      if (a > largest) largest = a, c.component = nq + i, c.acceleration = yp[nq + i];
    }
  if (largest <= 0) return c; // at rest with nothing acting, or no mass at all
  c.imbalance = force_scale > 0 ? largest / force_scale : std::numeric_limits<double>::infinity();
  c.name = system.component_name(c.component);
  c.unit = "1/s^2 (modal)"; // a flexible body's modal coordinate, unless a frame's below
  const unsigned int i = c.component - nq;
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    if (i >= system.v_offset(b) && i < system.v_offset(b) + std::min(6u, system.body(b).n_v()))
      c.unit = i - system.v_offset(b) < 3 ? "m/s^2" : "rad/s^2";
  return c;
}

std::string EquilibriumCheck::note() const
{
  std::ostringstream s;
  s << std::setprecision(3) << "the state linearised about is not an equilibrium or a steady motion: the largest "
    << "acceleration is d/dt '" << name << "' = " << acceleration << " " << unit << " (unbalanced: " << imbalance
    << " of the largest force acting, mass-weighted; an equilibrium leaves at most " << tolerance
    << "). The eigenvalues describe the motion near this instant only; for those of the equilibrium set "
       "'Multibody/Initial state = static equilibrium' or start at rest where the loads balance";
  return s.str();
}
} // namespace flextrack::multibody
