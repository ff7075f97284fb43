// Consistent initial conditions and redundant equations (initial_conditions.h).
#include <base/input_error.h>
#include <multibody/initial_conditions.h>
#include <multibody/redundancy.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <iomanip>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
/// M^-1 with a unit weight on coordinates without mass (a joint's own coordinates).
LAPACKFullMatrix<double> weight_inverse(const System &system, const Vector<double> &y)
{
  FullMatrix<double> M;
  system.mass_matrix(y, M);
  for (unsigned int i = 0; i < M.m(); ++i)
    if (M(i, i) == 0) M(i, i) = 1;
  LAPACKFullMatrix<double> W(M.m());
  W = M;
  W.invert();
  return W;
}

/// dx = -W B^T (B W B^T)^+ r: the mass-weighted minimum-norm solution of B dx = -r.
Vector<double> minimum_norm_correction(const LAPACKFullMatrix<double> &W, const FullMatrix<double> &B,
                                       const Vector<double> &r)
{
  const unsigned int m = B.m(), n = W.m(); // B may be 0 x 0 when there are no rows
  Vector<double> dx(n);
  if (m == 0) return dx;
  LAPACKFullMatrix<double> Bl(m, n), WBt(n, m), S(m, m);
  Bl = B;
  W.mTmult(WBt, Bl);   // W B^T (W symmetric)
  Bl.mmult(S, WBt);    // B W B^T
  // z = S^+ r from the SVD S = U diag(s) V^T, singular values below 1e-10 s_max dropped
  // (LAPACKFullMatrix::vmult does not apply the inverse after compute_inverse_svd()).
  S.compute_svd();
  const LAPACKFullMatrix<double> &U = S.get_svd_u(), &Vt = S.get_svd_vt();
  Vector<double> z(m);
  for (unsigned int i = 0; i < m; ++i)
    {
      const double s_i = S.singular_value(i);
      if (s_i <= 1e-10 * S.singular_value(0)) continue;
      double c = 0;
      for (unsigned int k = 0; k < m; ++k) c += U(k, i) * r[k];
      for (unsigned int k = 0; k < m; ++k) z[k] += Vt(i, k) * c / s_i;
    }
  WBt.vmult(dx, z);
  dx *= -1;
  return dx;
}

double max_abs(const Vector<double> &v) { return v.size() ? v.linfty_norm() : 0.0; }

[[noreturn]] void refuse_inconsistent(const System &system, const Vector<double> &phi, const double tolerance,
                                      const unsigned int iterations)
{
  const auto rows = system.constraint_rows(true);
  std::string joints;
  double worst = 0;
  for (unsigned int r = 0; r < rows.size(); ++r)
    if (std::abs(phi[r]) > tolerance)
      {
        const std::string name = system.joint(rows[r].first).name();
        if (joints.find("'" + name + "'") == std::string::npos) joints += (joints.empty() ? "'" : ", '") + name + "'";
        worst = std::max(worst, std::abs(phi[r]));
      }
  std::ostringstream s;
  s << "the initial conditions cannot be made consistent: after " << iterations
    << " Gauss-Newton iterations the constraints of joints " << joints << " are still violated by up to "
    << std::setprecision(3) << worst
    << " (m or rad): the joints conflict (a closed loop that cannot close, or redundant joints that disagree), "
       "or the initial positions are too far from an assembled configuration";
  throw InputError("Joints", s.str());
}

/// A dropped equation must also hold at velocity level with the projected velocities: a driver
/// that duplicates what other joints hold fixed (or two drivers of one motion) conflicts there.
/// A row is dropped when it is dependent to within @p rank_tolerance (relative), so its velocity
/// residual may be up to that fraction of |B_r| |v| without a conflict: 3.8e-8 m/s (against a
/// fixed 1e3 x 1e-11) was called a conflict in a consistent scene.
void refuse_conflicting_velocities(const System &system, const double t0, const Vector<double> &y, const double tolerance,
                                   const double rank_tolerance)
{
  Vector<double> phi, phi_t, v(system.n_v());
  FullMatrix<double> B;
  system.constraints(t0, y, true, phi, B, phi_t);
  for (unsigned int i = 0; i < system.n_v(); ++i) v[i] = y[system.n_q() + i];
  // What a row dependent to within rank_tolerance may leave: its remainder (at most rank_tolerance
  // |B_r|) times |v| (Cauchy-Schwarz).
  Vector<double> allowed_remainder(phi_t.size());
  for (unsigned int r = 0; r < phi_t.size(); ++r)
    {
      double row_norm = 0;
      for (unsigned int k = 0; k < B.n(); ++k) row_norm += B(r, k) * B(r, k);
      allowed_remainder[r] = 10 * rank_tolerance * std::sqrt(row_norm) * v.l2_norm();
    }
  if (B.m()) B.vmult_add(phi_t, v);
  const auto rows = system.constraint_rows(true);
  std::string joints;
  double worst = 0;
  for (unsigned int r = 0; r < rows.size(); ++r)
    if (std::abs(phi_t[r]) > 1e3 * tolerance + allowed_remainder[r])
      {
        const std::string name = system.joint(rows[r].first).name();
        if (joints.find("'" + name + "'") == std::string::npos) joints += (joints.empty() ? "'" : ", '") + name + "'";
        worst = std::max(worst, std::abs(phi_t[r]));
      }
  if (joints.empty()) return;
  std::ostringstream s;
  s << "conflicting joints: the equations of joint(s) " << joints
    << " depend on those of other joints but prescribe a different motion (velocity mismatch up to "
    << std::setprecision(3) << worst << " m/s or rad/s), e.g. a driver on a motion that other joints lock";
  throw InputError("Joints", s.str());
}

/// Gauss-Newton projection of the positions onto Phi = 0 (all equations).
unsigned int project_positions(const System &system, const double t0, Vector<double> &y,
                               const InitialConditionSettings &settings)
{
  Vector<double> phi, phi_t;
  FullMatrix<double> B;
  for (unsigned int it = 0; it < settings.max_iterations; ++it)
    {
      system.constraints(t0, y, true, phi, B, phi_t);
      if (max_abs(phi) <= settings.tolerance) return it;
      const Vector<double> dx = minimum_norm_correction(weight_inverse(system, y), B, phi);
      system.move_positions(y, dx);
    }
  system.constraints(t0, y, true, phi, B, phi_t);
  if (max_abs(phi) > settings.tolerance) refuse_inconsistent(system, phi, settings.tolerance, settings.max_iterations);
  return settings.max_iterations;
}
} // namespace

void consistent_derivatives(System &system, const double t, Vector<double> &y, Vector<double> &yp)
{
  const unsigned int nq = system.n_q(), nv = system.n_v(), nl = system.n_lambda();
  Vector<double> phi, phi_t, Q;
  FullMatrix<double> B, M;
  system.constraints(t, y, false, phi, B, phi_t);
  system.mass_matrix(y, M);
  system.generalized_forces(t, y, Q);

  // gamma = -d/dt (B v + Phi_t) along q' = T v at fixed v
  const double eps = 1e-6;
  Vector<double> v(nv), g_plus, g_minus;
  for (unsigned int i = 0; i < nv; ++i) v[i] = y[nq + i];
  auto velocity_constraint = [&](const double s, Vector<double> &g) {
    Vector<double> ys(y), dx(v);
    dx *= s;
    system.move_positions(ys, dx);
    Vector<double> p, pt;
    FullMatrix<double> Bs;
    system.constraints(t + s, ys, false, p, Bs, pt);
    g = pt;
    if (p.size()) Bs.vmult_add(g, v);
  };
  velocity_constraint(eps, g_plus);
  velocity_constraint(-eps, g_minus);

  LAPACKFullMatrix<double> K(nv + nl);
  Vector<double> rhs(nv + nl);
  for (unsigned int i = 0; i < nv; ++i)
    {
      rhs[i] = Q[i];
      for (unsigned int k = 0; k < nv; ++k) K(i, k) = M(i, k);
    }
  for (unsigned int r = 0; r < nl; ++r)
    {
      rhs[nv + r] = -(g_plus[r] - g_minus[r]) / (2 * eps);
      for (unsigned int k = 0; k < nv; ++k) K(nv + r, k) = K(k, nv + r) = B(r, k);
    }
  // A coordinate held at an end stop: its row reads v' = 0 (its force balance is the stop's).
  auto hold_rows = [&](Vector<double> &b) {
    for (unsigned int i = 0; i < nv; ++i)
      if (system.velocity_held(i)) b[i] = 0;
  };
  for (unsigned int i = 0; i < nv; ++i)
    if (system.velocity_held(i))
      {
        for (unsigned int k = 0; k < nv + nl; ++k) K(i, k) = 0;
        K(i, i) = 1;
      }
  hold_rows(rhs);
  K.compute_lu_factorization();
  const Vector<double> rhs0(rhs);
  K.solve(rhs);
  // Forces that depend on the accelerations (geometric stiffness of a flexible body's frame
  // accelerations, a small term): a few fixed-point passes with the last v'.
  bool implicit = false;
  for (unsigned int b = 0; b < system.n_bodies(); ++b) implicit |= system.body(b).forces_depend_on_acceleration();
  for (unsigned int pass = 0; implicit && pass < 3; ++pass)
    {
      Vector<double> v_dot(nv);
      for (unsigned int i = 0; i < nv; ++i) v_dot[i] = rhs[i];
      system.generalized_forces(t, y, Q, &v_dot);
      rhs = rhs0;
      for (unsigned int i = 0; i < nv; ++i) rhs[i] = Q[i];
      hold_rows(rhs);
      K.solve(rhs);
    }

  Vector<double> q_dot;
  system.coordinate_rates(y, q_dot);
  yp.reinit(system.size());
  for (unsigned int i = 0; i < nq; ++i) yp[i] = q_dot[i];
  for (unsigned int i = 0; i < nv; ++i) yp[nq + i] = rhs[i];
  for (unsigned int r = 0; r < nl; ++r) y[nq + nv + r] = rhs[nv + r];
  for (unsigned int r = 0; r < system.n_mu(); ++r) y[nq + nv + nl + r] = 0;
}

void project_velocities(const System &system, const double t, Vector<double> &y,
                        const std::vector<std::pair<unsigned int, double>> &prescribed)
{
  Vector<double> phi, phi_t;
  FullMatrix<double> B;
  system.constraints(t, y, false, phi, B, phi_t);
  const unsigned int nq = system.n_q(), nv = system.n_v(), m = B.m(), n = m + prescribed.size();
  FullMatrix<double> Bx(n, nv);
  Vector<double> v(nv), r(n);
  for (unsigned int i = 0; i < nv; ++i) v[i] = y[nq + i];
  for (unsigned int row = 0; row < m; ++row)
    {
      r[row] = phi_t[row];
      for (unsigned int k = 0; k < nv; ++k)
        {
          Bx(row, k) = B(row, k);
          r[row] += B(row, k) * v[k];
        }
    }
  for (unsigned int p = 0; p < prescribed.size(); ++p)
    {
      const unsigned int k = prescribed[p].first - nq;
      Bx(m + p, k) = 1;
      r[m + p] = v[k] - prescribed[p].second;
    }
  const Vector<double> dv = minimum_norm_correction(weight_inverse(system, y), Bx, r);
  for (unsigned int i = 0; i < nv; ++i) y[nq + i] += dv[i];
}

InitialConditionReport consistent_initial_conditions(System &system, const double t0, Vector<double> &y,
                                                     Vector<double> &yp, const InitialConditionSettings &settings)
{
  InitialConditionReport report;
  system.initial_guess(y);
  const Vector<double> y0 = y;
  system.move_positions(y, Vector<double>(system.n_v())); // normalises p
  report.iterations = project_positions(system, t0, y, settings);

  // Redundant equations: dependent at the projected configuration and nearby (a singular start
  // is refused there); the scales of the equations let the run watch the dropped ones.
  RedundancySettings redundancy;
  redundancy.rank_tolerance = settings.rank_tolerance;
  const RedundancyAnalysis analysis = find_redundant_equations(system, t0, y, redundancy);
  system.set_equation_scales(analysis.equation_scales);
  system.drop_equations(analysis.redundant);
  report.dropped = system.dropped_equations();
  report.neighbours_checked = analysis.neighbours_checked;
  report.neighbour_distance = redundancy.step * analysis.length_scale;
  y.grow_or_shrink(system.size());
  if (settings.static_equilibrium)
    {
      report.equilibrium = solve_static_equilibrium(system, t0, y, settings.equilibrium);
    }

  // Velocities onto B v + Phi_t = 0 (active equations: B has full row rank now)
  Vector<double> phi, phi_t;
  FullMatrix<double> B;
  system.constraints(t0, y, false, phi, B, phi_t);
  const unsigned int nq = system.n_q(), nv = system.n_v();
  Vector<double> v(nv), r(phi_t);
  for (unsigned int i = 0; i < nv; ++i) v[i] = y[nq + i];
  if (B.m()) B.vmult_add(r, v);
  const Vector<double> dv = minimum_norm_correction(weight_inverse(system, y), B, r);
  for (unsigned int i = 0; i < nv; ++i) y[nq + i] += dv[i];
  refuse_conflicting_velocities(system, t0, y, settings.tolerance, settings.rank_tolerance);
  consistent_derivatives(system, t0, y, yp);

  system.constraints(t0, y, true, phi, B, phi_t); // every equation, the dropped ones included
  for (unsigned int i = 0; i < nv; ++i) v[i] = y[nq + i];
  r = phi_t;
  if (B.m()) B.vmult_add(r, v);
  report.position_residual = max_abs(phi);
  report.velocity_residual = max_abs(r);

  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      const Body &body = system.body(b);
      const unsigned int q0 = system.q_offset(b), v0 = nq + system.v_offset(b);
      BodyCorrection c;
      c.body = body.name();
      double dp = 0, n0 = 0;
      for (unsigned int a = 0; a < 3; ++a) c.displacement += std::pow(y[q0 + a] - y0[q0 + a], 2);
      for (unsigned int a = 0; a < 4; ++a) dp += y[q0 + 3 + a] * y0[q0 + 3 + a], n0 += y0[q0 + 3 + a] * y0[q0 + 3 + a];
      c.displacement = std::sqrt(c.displacement);
      c.rotation = 2 * std::acos(std::min(1.0, std::abs(dp) / std::sqrt(n0)));
      for (unsigned int k = 0; k < body.n_modes(); ++k) c.modal += std::pow(y[q0 + 7 + k] - y0[q0 + 7 + k], 2);
      c.modal = std::sqrt(c.modal);
      for (unsigned int k = 0; k < body.n_v(); ++k) c.velocity += std::pow(y[v0 + k] - y0[v0 + k], 2);
      c.velocity = std::sqrt(c.velocity);
      report.corrections.push_back(c);
    }
  return report;
}

std::string InitialConditionReport::text() const
{
  std::ostringstream s;
  s << std::setprecision(3);
  s << "Initial conditions: positions projected in " << iterations << " iteration(s); |Phi| = " << position_residual
    << ", |B v + Phi_t| = " << velocity_residual << "\n";
  for (const auto &c : corrections)
    s << "  body " << c.body << ": moved " << c.displacement << " m, turned " << c.rotation << " rad"
      << (c.modal > 0 ? ", modal change " + std::to_string(c.modal) : std::string()) << ", velocity change "
      << c.velocity << "\n";
  s << equilibrium.text();
  for (const auto &d : dropped)
    s << "  redundant: joint " << d.joint << ", equation " << d.equation << " (" << d.description
      << ") dropped; its reaction is not unique\n";
  if (!dropped.empty())
    s << "  (dependent at the start and at " << neighbours_checked << " assembled configuration(s) " << neighbour_distance
      << " m away; watched during the run)\n";
  return s.str();
}
} // namespace flextrack::multibody
