// Static equilibrium by a damped Newton iteration (static_equilibrium.h).
#include <base/input_error.h>
#include <multibody/linearization.h>
#include <multibody/redundancy.h>
#include <multibody/static_equilibrium.h>
#include <multibody/static_stiffness.h>

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

/// The augmented matrix J = [K B^T; B 0] equilibrated (rows, then columns, by their largest
/// entries) and its SVD.
struct ScaledMatrix
{
  Vector<double> row_scale, col_scale;
  LAPACKFullMatrix<double> S;
  double s_max = 0, s_min = 0;

  explicit ScaledMatrix(const FullMatrix<double> &J)
    : row_scale(J.m()), col_scale(J.m()), S(J.m(), J.m())
  {
    const unsigned int n = J.m();
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
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j) S(i, j) = row_scale[i] * J(i, j) * col_scale[j];
    S.compute_svd();
    s_max = S.singular_value(0);
    s_min = S.singular_value(n - 1);
  }
  bool singular(const double tolerance) const { return !(s_min > tolerance * s_max); }
  /// The step solving J step = -r (singular values below @p tolerance x the largest left out).
  Vector<double> step(const Vector<double> &r, const double tolerance) const
  {
    const unsigned int n = r.size();
    Vector<double> z(n), step(n);
    const auto &U = S.get_svd_u(), &Vt = S.get_svd_vt();
    for (unsigned int k = 0; k < n; ++k)
      {
        if (!(S.singular_value(k) > tolerance * s_max)) continue;
        double c = 0;
        for (unsigned int i = 0; i < n; ++i) c -= U(i, k) * row_scale[i] * r[i];
        c /= S.singular_value(k);
        for (unsigned int j = 0; j < n; ++j) z[j] += Vt(k, j) * c;
      }
    for (unsigned int j = 0; j < n; ++j) step[j] = col_scale[j] * z[j];
    return step;
  }
  /// True if @p r is balanced along every singular direction: its part along each left singular
  /// vector u_k of a singular value below @p tolerance x the largest is within the part of the
  /// tolerances @p allowed (per row) along u_k.
  bool balanced_along_singular_directions(const Vector<double> &r, const Vector<double> &allowed,
                                          const double tolerance) const
  {
    const unsigned int n = r.size();
    const auto &U = S.get_svd_u();
    for (unsigned int k = 0; k < n; ++k)
      {
        if (S.singular_value(k) > tolerance * s_max) continue;
        double along = 0, bound = 0;
        for (unsigned int i = 0; i < n; ++i)
          along += U(i, k) * row_scale[i] * r[i], bound += std::abs(U(i, k)) * row_scale[i] * allowed[i];
        if (std::abs(along) > bound) return false;
      }
    return true;
  }
  /// The velocity coordinate (< @p nv) that moves most along the last right singular vector.
  unsigned int singular_motion(const unsigned int nv) const
  {
    const unsigned int last = S.m() - 1;
    unsigned int worst = 0;
    for (unsigned int j = 0; j < nv; ++j)
      if (std::abs(S.get_svd_vt()(last, j)) > std::abs(S.get_svd_vt()(last, worst))) worst = j;
    return worst;
  }
};

/// [K B^T; B 0] (n_v + n_l square).
FullMatrix<double> augmented(const FullMatrix<double> &K, const FullMatrix<double> &B)
{
  const unsigned int nv = K.m(), nl = B.m();
  FullMatrix<double> J(nv + nl, nv + nl);
  for (unsigned int i = 0; i < nv; ++i)
    for (unsigned int c = 0; c < nv; ++c) J(i, c) = K(i, c);
  for (unsigned int k = 0; k < nl; ++k)
    for (unsigned int c = 0; c < nv; ++c) J(nv + k, c) = J(c, nv + k) = B(k, c);
  return J;
}

/// What the shifted step needs of the motions the joints allow (the null space Z of B): the
/// eigenvalues of the symmetric part of K_T against M on it (Z^T K_s Z w = omega^2 Z^T M Z w,
/// [1/s^2]: negative for a motion that the loads push further, e.g. an inverted pendulum) and the
/// acceleration that the unbalanced force @p r_f (its first n_v rows) gives along them,
/// Z (Z^T M Z)^+ Z^T r_f (velocity coordinates: m/s^2, rad/s^2, modal).
struct AllowedMotions
{
  double lowest = 0, largest = 0; ///< smallest eigenvalue, largest |eigenvalue| [1/s^2]
  Vector<double> acceleration;
};
AllowedMotions allowed_motions(const FullMatrix<double> &K, const FullMatrix<double> &M, const FullMatrix<double> &B,
                               const Vector<double> &r)
{
  const unsigned int nv = K.m();
  AllowedMotions a;
  a.acceleration.reinit(nv);
  const FullMatrix<double> Z = constraint_null_space(B, nv);
  const unsigned int nf = Z.n();
  if (nf == 0) return a;
  FullMatrix<double> Ks(nv, nv), Kr(nf, nf), Mr(nf, nf);
  for (unsigned int i = 0; i < nv; ++i)
    for (unsigned int j = 0; j < nv; ++j) Ks(i, j) = 0.5 * (K(i, j) + K(j, i));
  Kr.triple_product(Ks, Z, Z, true, false);
  Mr.triple_product(M, Z, Z, true, false);
  // M-orthonormal basis W of the allowed motions with mass: Mr = U diag(m) U^T, W = U m^-1/2.
  LAPACKFullMatrix<double> Ml(nf, nf);
  Ml = Mr;
  Ml.compute_svd();
  std::vector<unsigned int> kept;
  for (unsigned int k = 0; k < nf; ++k)
    if (Ml.singular_value(k) > 1e-12 * Ml.singular_value(0)) kept.push_back(k);
  const unsigned int nw = kept.size();
  if (nw == 0) return a;
  FullMatrix<double> W(nf, nw), A(nw, nw);
  for (unsigned int c = 0; c < nw; ++c)
    for (unsigned int i = 0; i < nf; ++i) W(i, c) = Ml.get_svd_u()(i, kept[c]) / std::sqrt(Ml.singular_value(kept[c]));
  A.triple_product(Kr, W, W, true, false);
  LAPACKFullMatrix<double> Al(nw, nw);
  Al = A;
  Al.compute_eigenvalues();
  a.lowest = Al.eigenvalue(0).real();
  for (unsigned int k = 0; k < nw; ++k)
    a.lowest = std::min(a.lowest, Al.eigenvalue(k).real()), a.largest = std::max(a.largest, std::abs(Al.eigenvalue(k)));
  // acceleration = Z W W^T Z^T r_f
  Vector<double> rf(nv), zr(nf), wr(nw), w(nf);
  for (unsigned int i = 0; i < nv; ++i) rf[i] = r[i];
  Z.Tvmult(zr, rf);
  W.Tvmult(wr, zr);
  W.vmult(w, wr);
  Z.vmult(a.acceleration, w);
  return a;
}
} // namespace

EquilibriumReport solve_static_equilibrium(System &system, const double t0, Vector<double> &y,
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
  Vector<double> allowed(n); // the tolerance of each residual row
  for (unsigned int i = 0; i < n; ++i) allowed[i] = i < nv ? force_tolerance : settings.position_tolerance;
  const double length = scene_length_scale(system, y); // [m], for the shifted steps

  // Multipliers of least (weighted) squares of B^T lambda - Q at the positions of @p yy, row i
  // weighted by w_i (B has full row rank: redundant equations are dropped).
  auto least_squares_multipliers = [&](const Vector<double> &yy, const Vector<double> &w) {
    Vector<double> phi, phi_t, Qy, BQ(nl);
    FullMatrix<double> B0;
    system.generalized_forces(t0, yy, Qy);
    system.constraints(t0, yy, false, phi, B0, phi_t);
    if (nl == 0) return BQ;
    LAPACKFullMatrix<double> BBt(nl, nl);
    for (unsigned int i = 0; i < nl; ++i)
      {
        for (unsigned int c = 0; c < nv; ++c) BQ[i] += B0(i, c) * w[c] * w[c] * Qy[c];
        for (unsigned int j = 0; j < nl; ++j)
          for (unsigned int c = 0; c < nv; ++c) BBt(i, j) += B0(i, c) * w[c] * w[c] * B0(j, c);
      }
    BBt.compute_lu_factorization();
    BBt.solve(BQ);
    return BQ;
  };
  // First multipliers: least squares of B^T lambda = Q. With lambda = 0 a rigid pendulum would
  // have no stiffness at all: its restoring stiffness is the constraint force turning with the
  // body, d(B^T lambda)/dq.
  Vector<double> r, r_trial, unit(n);
  unit = 1;
  Vector<double> lambda = least_squares_multipliers(y, unit);
  static_residual(system, t0, y, lambda, r);
  auto converged = [&](const Vector<double> &res) {
    double f = 0, c = 0;
    for (unsigned int i = 0; i < nv; ++i) f = std::max(f, std::abs(res[i]));
    for (unsigned int i = nv; i < n; ++i) c = std::max(c, std::abs(res[i]));
    return f <= force_tolerance && c <= settings.position_tolerance;
  };
  auto refuse_as_mechanism = [&](const ScaledMatrix &S) {
    std::ostringstream s;
    s << std::setprecision(3)
      << "'static equilibrium': the scene is a mechanism under these loads: the static stiffness is singular "
         "(smallest singular value "
      << S.s_min / S.s_max << " of the largest, equilibrated) along '" << system.component_name(nq + S.singular_motion(nv))
      << "', a motion that no joint, driver, spring or load holds, so there is no unique equilibrium. Hold that "
         "motion (a joint, a driver, a spring), or set 'Initial state = as given'";
    throw InputError(entry, s.str());
  };

  Vector<double> row_scale(n);
  auto merit = [&](const Vector<double> &res) {
    double s = 0;
    for (unsigned int i = 0; i < n; ++i) s += std::pow(row_scale[i] * res[i], 2);
    return std::sqrt(s);
  };
  // Moves to y + alpha step (positions) and lambda + alpha step; true if the residual there
  // decreases enough (or converges): then y, lambda and r are the trial's.
  Vector<double> y_trial, lambda_trial(nl), dx(nv);
  auto try_step = [&](const Vector<double> &step, const double alpha, const double m0) {
    y_trial = y;
    for (unsigned int j = 0; j < nv; ++j) dx[j] = alpha * step[j];
    system.move_positions(y_trial, dx);
    for (unsigned int k = 0; k < nl; ++k) lambda_trial[k] = lambda[k] + alpha * step[nv + k];
    static_residual(system, t0, y_trial, lambda_trial, r_trial);
    if (!(merit(r_trial) < (1 - 1e-4 * alpha) * m0 || converged(r_trial))) return false;
    y = y_trial;
    lambda = lambda_trial;
    r = r_trial;
    return true;
  };
  // The largest alpha <= 1 that keeps every body's rotation within max_turn [rad] (and, if
  // max_shift > 0, its frame's displacement within max_shift [m]).
  auto limited = [&](const Vector<double> &step, const double max_turn, const double max_shift) {
    double alpha = 1;
    for (unsigned int b = 1; b < system.n_bodies(); ++b)
      for (unsigned int a = 0; a < std::min(6u, system.body(b).n_v()); ++a)
        {
          const double size = std::abs(step[system.v_offset(b) + a]);
          if (a >= 3) alpha = std::min(alpha, max_turn / std::max(1e-300, size));
          else if (max_shift > 0) alpha = std::min(alpha, max_shift / std::max(1e-300, size));
        }
    return alpha;
  };

  FullMatrix<double> K(nv, nv), B, M;
  unsigned int it = 0;
  bool last_singular = false; // the last tangent was singular (and unbalanced along it)
  std::string singular_along;
  // Set at the first step without Newton: from then on the iteration goes downhill (Newton only
  // where the stiffness on the allowed motions is positive), to a stable equilibrium.
  bool descending = false;
  for (; it < settings.max_iterations; ++it)
    {
      // One tangent at least, also when the start is balanced already: a slider on a level guide
      // is in equilibrium anywhere, and only the singular tangent tells.
      if (it > 0 && converged(r)) break;
      // Tangent: K_T from the DAE Jacobian (static_stiffness.h), B and B^T analytic.
      static_stiffness(system, t0, y, lambda, K, B);
      const ScaledMatrix S(augmented(K, B));
      row_scale = S.row_scale;
      const double m0 = merit(r);
      last_singular = S.singular(settings.singular_tolerance);
      if (last_singular)
        {
          // Nothing holds the motion and nothing pushes along it: a mechanism. Otherwise (a
          // pendulum started horizontal) the shifted step below moves it on.
          if (S.balanced_along_singular_directions(r, allowed, settings.singular_tolerance)) refuse_as_mechanism(S);
          singular_along = system.component_name(nq + S.singular_motion(nv));
        }
      AllowedMotions motions;
      bool have_motions = false;
      auto find_motions = [&]() {
        if (have_motions) return;
        system.mass_matrix(y, M);
        motions = allowed_motions(K, M, B, r);
        have_motions = true;
      };
      bool newton = !last_singular;
      if (newton && descending)
        {
          // Going downhill already: no Newton step towards a maximum or a saddle (an indefinite
          // stiffness on the allowed motions; round-off aside).
          find_motions();
          newton = !(motions.lowest < -1e-12 * motions.largest);
        }
      if (newton)
        {
          // Newton step, at most 0.5 rad of rotation (a turn too far could leap to another
          // equilibrium), halved until the residual decreases.
          const Vector<double> step = S.step(r, 0);
          double alpha = limited(step, 0.5, 0);
          bool accepted = false;
          for (unsigned int cut = 0; cut < 30 && !accepted; ++cut, alpha *= 0.5) accepted = try_step(step, alpha, m0);
          if (accepted) continue;
        }

      // No Newton step (or none downhill): the mass-shifted tangent K_T + mu M.
      descending = true;
      find_motions();
      double mu_load = 0; // the unbalanced acceleration over 0.25 rad or 0.25 of the scene's size
      for (unsigned int b = 1; b < system.n_bodies(); ++b)
        for (unsigned int a = 0; a < std::min(6u, system.body(b).n_v()); ++a)
          mu_load = std::max(mu_load, std::abs(motions.acceleration[system.v_offset(b) + a]) / (a < 3 ? 0.25 * length : 0.25));
      double mu = std::max({2 * std::max(0.0, -motions.lowest), mu_load, 1e-10 * motions.largest});
      if (!(mu > 0)) mu = 1; // nothing to scale by (no allowed motion with mass): any positive shift
      // The shifted step is taken as it is (at most 0.5 rad and 0.5 L), not judged by the
      // residual: going downhill from a stationary point (a pendulum started horizontal, or near
      // its top) the unbalanced load first grows, and the residual's weights change from one
      // tangent to the next. The multipliers are then those of least (weighted) squares at the
      // new positions, a start for Newton's next tangent that holds the link forces.
      FullMatrix<double> Kmu(K);
      Kmu.add(mu, M);
      const Vector<double> step = ScaledMatrix(augmented(Kmu, B)).step(r, settings.singular_tolerance);
      const double alpha = limited(step, 0.5, 0.5 * length);
      for (unsigned int j = 0; j < nv; ++j) dx[j] = alpha * step[j];
      y_trial = y;
      system.move_positions(y_trial, dx);
      lambda_trial = least_squares_multipliers(y_trial, row_scale);
      static_residual(system, t0, y_trial, lambda_trial, r_trial);
      bool finite = true;
      for (unsigned int i = 0; i < n; ++i) finite = finite && std::isfinite(r_trial[i]);
      if (!finite) break; // reported below as not converged
      y = y_trial;
      lambda = lambda_trial;
      r = r_trial;
      ++report.shifted_steps;
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
          const double ratio = std::abs(r[i]) / allowed[i];
          if (ratio > worst_ratio) worst_ratio = ratio, worst = i;
        }
      std::ostringstream s;
      s << std::setprecision(3) << "'static equilibrium': no equilibrium found: after " << it
        << " damped Newton iterations the largest residual is " << r[worst] << " in the " << row_name(system, worst)
        << " (tolerance " << allowed[worst] << (worst < nv ? " N, N m or modal force" : " m or rad") << ")";
      if (last_singular)
        s << "; the static stiffness is singular along '" << singular_along
          << "', a motion that nothing holds against the load on it";
      s << ". The loads may be more than the structure can carry (a torque above the largest restoring moment, a "
           "flexible body pushed past its linear range), or the start is too far from the equilibrium: start "
           "closer (Position, Rotation vector, Modal coordinates), or set 'Initial state = as given'";
      throw InputError(entry, s.str());
    }
  // Balanced, but is it unique? A tangent singular at the equilibrium found is a mechanism too.
  static_stiffness(system, t0, y, lambda, K, B);
  {
    const ScaledMatrix S(augmented(K, B));
    if (S.singular(settings.singular_tolerance)) refuse_as_mechanism(S);
  }

  // Stability: the linearisation about the equilibrium, judged as 'flextrack linearize' judges it
  // (an inverted pendulum is an equilibrium too).
  {
    const StabilityVerdict verdict = classify_stability(linearize(system, t0, y));
    report.stable = verdict.stable();
    report.unstable_modes = verdict.unstable_modes;
    report.growth_rate = verdict.largest_growth_rate;
  }
  report.moves = moves(system, y0, y);
  return report;
}

std::string EquilibriumReport::text() const
{
  if (!solved) return "";
  std::ostringstream s;
  s << std::setprecision(3) << "Static equilibrium: " << iterations << " Newton iteration(s)";
  if (shifted_steps) s << " (" << shifted_steps << " with the mass-shifted tangent K_T + mu M: Newton had no step)";
  s << "; max |B^T lambda - Q| = " << force_residual << " (largest load " << load_scale << "), |Phi| = " << position_residual;
  if (!stable)
    s << std::setprecision(9) << "; UNSTABLE: linearised about it, " << unstable_modes
      << " mode(s) grow, the fastest at Re s = " << growth_rate
      << " 1/s (e.g. an inverted pendulum); the run will leave it";
  s << "\n" << std::setprecision(3);
  for (const auto &m : moves)
    s << "  body " << m.body << ": moved " << m.displacement << " m, turned " << m.rotation << " rad"
      << (m.modal > 0 ? ", modal change " + std::to_string(m.modal) : std::string()) << "\n";
  return s.str();
}
} // namespace flextrack::multibody
