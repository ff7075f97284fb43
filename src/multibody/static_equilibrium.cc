// Static equilibrium by a damped Newton iteration (static_equilibrium.h).
#include <base/input_error.h>
#include <multibody/static_equilibrium.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
const char *const entry = "Multibody/Initial state";

double max_abs(const Vector<double> &v) { return v.size() ? v.linfty_norm() : 0.0; }

/// r = (B^T lambda - Q, Phi) at the positions of @p y (velocities zero) and @p lambda.
void static_residual(const System &system, const double t0, const Vector<double> &y, const Vector<double> &lambda,
                     Vector<double> &r)
{
  const unsigned int nv = system.n_v(), nl = system.n_lambda();
  Vector<double> Q, phi, phi_t;
  FullMatrix<double> B;
  system.generalized_forces(t0, y, Q);
  system.constraints(t0, y, false, phi, B, phi_t);
  r.reinit(nv + nl);
  for (unsigned int i = 0; i < nv; ++i) r[i] = -Q[i];
  for (unsigned int k = 0; k < nl; ++k)
    {
      for (unsigned int i = 0; i < nv; ++i) r[i] += B(k, i) * lambda[k];
      r[nv + k] = phi[k];
    }
}

/// K = d(B^T lambda - Q)/dx (nv x nv) at @p y by central differences of step @p h along the
/// velocity coordinates (positions moved by System::move_positions), and B at @p y.
void static_stiffness(const System &system, const double t0, const Vector<double> &y, const Vector<double> &lambda,
                      const double h, FullMatrix<double> &K, FullMatrix<double> &B)
{
  const unsigned int nv = system.n_v();
  Vector<double> phi, phi_t, r_plus, r_minus;
  system.constraints(t0, y, false, phi, B, phi_t);
  for (unsigned int c = 0; c < nv; ++c)
    {
      Vector<double> dx(nv), y_plus(y), y_minus(y);
      dx[c] = h;
      system.move_positions(y_plus, dx);
      dx[c] = -h;
      system.move_positions(y_minus, dx);
      static_residual(system, t0, y_plus, lambda, r_plus);
      static_residual(system, t0, y_minus, lambda, r_minus);
      for (unsigned int i = 0; i < nv; ++i) K(i, c) = (r_plus[i] - r_minus[i]) / (2 * h);
    }
}

/// The name of residual row @p i: a generalised force or a joint's position constraint.
std::string row_name(const System &system, const unsigned int i)
{
  if (i < system.n_v()) return "force balance of '" + system.component_name(system.n_q() + i) + "'";
  return "'" + system.component_name(system.n_q() + system.n_v() + system.n_lambda() + (i - system.n_v())) + "'";
}

/// Per-body change from @p y0 to @p y.
std::vector<EquilibriumMove> moves(const System &system, const Vector<double> &y0, const Vector<double> &y)
{
  std::vector<EquilibriumMove> m;
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      const Body &body = system.body(b);
      const unsigned int q0 = system.q_offset(b);
      EquilibriumMove c;
      c.body = body.name();
      double dp = 0, n0 = 0, n1 = 0;
      for (unsigned int a = 0; a < 3; ++a) c.displacement += std::pow(y[q0 + a] - y0[q0 + a], 2);
      for (unsigned int a = 0; a < 4; ++a)
        dp += y[q0 + 3 + a] * y0[q0 + 3 + a], n0 += y0[q0 + 3 + a] * y0[q0 + 3 + a], n1 += y[q0 + 3 + a] * y[q0 + 3 + a];
      c.displacement = std::sqrt(c.displacement);
      c.rotation = 2 * std::acos(std::min(1.0, std::abs(dp) / std::sqrt(n0 * n1)));
      for (unsigned int k = 0; k < body.n_modes(); ++k) c.modal += std::pow(y[q0 + 7 + k] - y0[q0 + 7 + k], 2);
      c.modal = std::sqrt(c.modal);
      m.push_back(c);
    }
  return m;
}

/// Smallest eigenvalue of the symmetric part of K_T on the null space of B (B: nl x nv).
double smallest_constrained_stiffness(const FullMatrix<double> &K, const FullMatrix<double> &B)
{
  const unsigned int nv = K.m(), nl = B.m();
  // Null-space basis Z of B: the right singular vectors beyond its rank.
  std::vector<Vector<double>> Z;
  if (nl == 0)
    for (unsigned int i = 0; i < nv; ++i)
      {
        Vector<double> z(nv);
        z[i] = 1;
        Z.push_back(z);
      }
  else
    {
      LAPACKFullMatrix<double> Bs(nv, nv); // B padded with zero rows to a square matrix
      for (unsigned int r = 0; r < nl; ++r)
        for (unsigned int c = 0; c < nv; ++c) Bs(r, c) = B(r, c);
      Bs.compute_svd();
      const double s0 = Bs.singular_value(0);
      for (unsigned int i = 0; i < nv; ++i)
        if (Bs.singular_value(i) <= 1e-10 * s0)
          {
            Vector<double> z(nv);
            for (unsigned int c = 0; c < nv; ++c) z[c] = Bs.get_svd_vt()(i, c);
            Z.push_back(z);
          }
    }
  if (Z.empty()) return 0;
  const unsigned int n = Z.size();
  LAPACKFullMatrix<double> S(n, n);
  Vector<double> Kz(nv);
  for (unsigned int j = 0; j < n; ++j)
    {
      K.vmult(Kz, Z[j]);
      for (unsigned int i = 0; i < n; ++i) S(i, j) += 0.5 * (Z[i] * Kz), S(j, i) += 0.5 * (Z[i] * Kz);
    }
  S.compute_eigenvalues();
  double smallest = S.eigenvalue(0).real();
  for (unsigned int i = 1; i < n; ++i) smallest = std::min(smallest, S.eigenvalue(i).real());
  return smallest;
}
} // namespace

EquilibriumReport solve_static_equilibrium(const System &system, const double t0, Vector<double> &y,
                                           const EquilibriumSettings &settings)
{
  const unsigned int nq = system.n_q(), nv = system.n_v(), nl = system.n_lambda(), n = nv + nl;
  EquilibriumReport report;
  report.solved = true;
  for (unsigned int i = 0; i < nv; ++i) y[nq + i] = 0; // at rest
  const Vector<double> y0(y);

  Vector<double> Q;
  system.generalized_forces(t0, y, Q);
  report.load_scale = max_abs(Q);
  const double force_tolerance = settings.relative_tolerance * (report.load_scale > 0 ? report.load_scale : 1.0);

  // First multipliers: least squares of B^T lambda = Q (B has full row rank: redundant
  // equations are dropped). With lambda = 0 a rigid pendulum would have no stiffness at all: its
  // restoring stiffness is the constraint force turning with the body, d(B^T lambda)/dq.
  Vector<double> lambda(nl), r, r_trial;
  if (nl > 0)
    {
      Vector<double> phi, phi_t, BQ(nl);
      FullMatrix<double> B0;
      system.constraints(t0, y, false, phi, B0, phi_t);
      B0.vmult(BQ, Q);
      LAPACKFullMatrix<double> BBt(nl, nl);
      for (unsigned int i = 0; i < nl; ++i)
        for (unsigned int j = 0; j < nl; ++j)
          for (unsigned int c = 0; c < nv; ++c) BBt(i, j) += B0(i, c) * B0(j, c);
      BBt.compute_lu_factorization();
      BBt.solve(BQ);
      lambda = BQ;
    }
  static_residual(system, t0, y, lambda, r);
  auto converged = [&](const Vector<double> &res) {
    double f = 0, c = 0;
    for (unsigned int i = 0; i < nv; ++i) f = std::max(f, std::abs(res[i]));
    for (unsigned int i = nv; i < n; ++i) c = std::max(c, std::abs(res[i]));
    return f <= force_tolerance && c <= settings.position_tolerance;
  };

  Vector<double> row_scale(n), col_scale(n);
  auto merit = [&](const Vector<double> &res) {
    double s = 0;
    for (unsigned int i = 0; i < n; ++i) s += std::pow(row_scale[i] * res[i], 2);
    return std::sqrt(s);
  };

  FullMatrix<double> J(n, n), K(nv, nv), B;
  const double h = 1e-6;
  unsigned int it = 0;
  for (; it < settings.max_iterations; ++it)
    {
      // One tangent at least, also when the start is balanced already: a slider on a level guide
      // is in equilibrium anywhere, and only the singular tangent tells.
      if (it > 0 && converged(r)) break;
      // Tangent: K_T by central differences of r_f, B and B^T analytic.
      static_stiffness(system, t0, y, lambda, h, K, B);
      J = 0;
      for (unsigned int i = 0; i < nv; ++i)
        for (unsigned int c = 0; c < nv; ++c) J(i, c) = K(i, c);
      for (unsigned int k = 0; k < nl; ++k)
        for (unsigned int c = 0; c < nv; ++c) J(nv + k, c) = J(c, nv + k) = B(k, c);

      // Equilibrate (rows, then columns, by their largest entries), SVD, singularity check.
      for (unsigned int i = 0; i < n; ++i)
        {
          double m = 0;
          for (unsigned int j = 0; j < n; ++j) m = std::max(m, std::abs(J(i, j)));
          row_scale[i] = m > 0 ? 1 / m : 1;
        }
      for (unsigned int j = 0; j < n; ++j)
        {
          double m = 0;
          for (unsigned int i = 0; i < n; ++i) m = std::max(m, std::abs(row_scale[i] * J(i, j)));
          col_scale[j] = m > 0 ? 1 / m : 1;
        }
      LAPACKFullMatrix<double> S(n, n);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = 0; j < n; ++j) S(i, j) = row_scale[i] * J(i, j) * col_scale[j];
      S.compute_svd();
      const double s_max = S.singular_value(0), s_min = S.singular_value(n - 1);
      if (!(s_min > settings.singular_tolerance * s_max))
        {
          // The coordinate that moves most along the singular direction (last right singular vector).
          unsigned int worst = 0;
          for (unsigned int j = 0; j < nv; ++j)
            if (std::abs(S.get_svd_vt()(n - 1, j)) > std::abs(S.get_svd_vt()(n - 1, worst))) worst = j;
          std::ostringstream s;
          s << std::setprecision(3)
            << "'static equilibrium': the scene is a mechanism under these loads: the static stiffness is singular "
               "(smallest singular value "
            << s_min / s_max << " of the largest, equilibrated) along '" << system.component_name(nq + worst)
            << "', a motion that no joint, driver, spring or load holds, so there is no unique equilibrium. Hold that "
               "motion (a joint, a driver, a spring), or set 'Initial state = as given'";
          throw InputError(entry, s.str());
        }
      // Newton step from the SVD: z = V diag(1/s) U^T (R r), dx = C z
      Vector<double> rhs(n), z(n), step(n);
      for (unsigned int i = 0; i < n; ++i) rhs[i] = -row_scale[i] * r[i];
      const auto &U = S.get_svd_u(), &Vt = S.get_svd_vt();
      for (unsigned int k = 0; k < n; ++k)
        {
          double c = 0;
          for (unsigned int i = 0; i < n; ++i) c += U(i, k) * rhs[i];
          c /= S.singular_value(k);
          for (unsigned int j = 0; j < n; ++j) z[j] += Vt(k, j) * c;
        }
      for (unsigned int j = 0; j < n; ++j) step[j] = col_scale[j] * z[j];

      // At most 0.5 rad of rotation per step (a turn too far could leap to another equilibrium).
      double alpha = 1;
      for (unsigned int b = 1; b < system.n_bodies(); ++b)
        for (unsigned int a = 3; a < 6; ++a)
          alpha = std::min(alpha, 0.5 / std::max(1e-300, std::abs(step[system.v_offset(b) + a])));
      const double m0 = merit(r);
      Vector<double> y_trial, lambda_trial(nl), dx(nv);
      bool accepted = false;
      for (unsigned int cut = 0; cut < 30; ++cut, alpha *= 0.5)
        {
          y_trial = y;
          for (unsigned int j = 0; j < nv; ++j) dx[j] = alpha * step[j];
          system.move_positions(y_trial, dx);
          for (unsigned int k = 0; k < nl; ++k) lambda_trial[k] = lambda[k] + alpha * step[nv + k];
          static_residual(system, t0, y_trial, lambda_trial, r_trial);
          if (merit(r_trial) < (1 - 1e-4 * alpha) * m0 || converged(r_trial))
            {
              accepted = true;
              break;
            }
        }
      if (!accepted) break; // no descent: reported below as not converged
      y = y_trial;
      lambda = lambda_trial;
      r = r_trial;
    }
  report.iterations = it;
  for (unsigned int i = 0; i < nv; ++i) report.force_residual = std::max(report.force_residual, std::abs(r[i]));
  for (unsigned int i = nv; i < n; ++i) report.position_residual = std::max(report.position_residual, std::abs(r[i]));
  if (!converged(r))
    {
      unsigned int worst = 0;
      double worst_ratio = 0;
      for (unsigned int i = 0; i < n; ++i)
        {
          const double ratio = std::abs(r[i]) / (i < nv ? force_tolerance : settings.position_tolerance);
          if (ratio > worst_ratio) worst_ratio = ratio, worst = i;
        }
      std::ostringstream s;
      s << std::setprecision(3) << "'static equilibrium': no equilibrium found: after " << it
        << " damped Newton iterations the largest residual is " << r[worst] << " in the " << row_name(system, worst)
        << " (tolerance " << (worst < nv ? force_tolerance : settings.position_tolerance)
        << (worst < nv ? " N, N m or modal force" : " m or rad")
        << "). The loads may be more than the structure can carry (a torque above the largest restoring moment, a "
           "flexible body pushed past its linear range), or the start is too far from the equilibrium: start "
           "closer (Position, Rotation vector, Modal coordinates), or set 'Initial state = as given'";
      throw InputError(entry, s.str());
    }

  // Stability: the stiffness on the constraint null space (an inverted pendulum is an equilibrium too).
  {
    static_stiffness(system, t0, y, lambda, h, K, B);
    report.smallest_stiffness = smallest_constrained_stiffness(K, B);
    report.stable = report.smallest_stiffness >= -1e-8 * K.linfty_norm(); // finite-difference noise
  }
  report.moves = moves(system, y0, y);
  return report;
}

std::string EquilibriumReport::text() const
{
  if (!solved) return "";
  std::ostringstream s;
  s << std::setprecision(3) << "Static equilibrium: " << iterations << " Newton iteration(s); max |B^T lambda - Q| = "
    << force_residual << " (largest load " << load_scale << "), |Phi| = " << position_residual
    << (stable ? "" : "; UNSTABLE: the stiffness on the constraint null space has a negative eigenvalue (e.g. an "
                      "inverted pendulum); the run will leave it")
    << "\n";
  for (const auto &m : moves)
    s << "  body " << m.body << ": moved " << m.displacement << " m, turned " << m.rotation << " rad"
      << (m.modal > 0 ? ", modal change " + std::to_string(m.modal) : std::string()) << "\n";
  return s.str();
}
} // namespace flextrack::multibody
