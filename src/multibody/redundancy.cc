// Redundant joint equations decided on a neighbourhood of the start (redundancy.h).
#include <base/input_error.h>
#include <multibody/redundancy.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <random>
#include <set>
#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
/// D: the scale of each velocity coordinate (x = D x~): L for translations and joints' own
/// coordinates (arc lengths), 1 for rotations, L sqrt(m / m_k) for a mode of modal mass m_k of a
/// body of mass m (a unit x~ then moves the body by about L, as a unit translation does).
Vector<double> coordinate_scales(const System &system, const Vector<double> &y, const double L)
{
  Vector<double> D(system.n_v());
  for (unsigned int i = 0; i < D.size(); ++i) D[i] = L; // own coordinates keep L
  FullMatrix<double> M;
  system.mass_matrix(y, M);
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      const unsigned int v = system.v_offset(b), n = system.body(b).n_v();
      const double m = M(v, v);
      for (unsigned int a = 3; a < 6; ++a) D[v + a] = 1;
      for (unsigned int k = 6; k < n; ++k) D[v + k] = M(v + k, v + k) > 0 && m > 0 ? L * std::sqrt(m / M(v + k, v + k)) : L;
    }
  return D;
}

/// B~ = S^-1 B D.
FullMatrix<double> scaled(const FullMatrix<double> &B, const Vector<double> &D, const std::vector<double> &s)
{
  FullMatrix<double> Bs(B.m(), B.n());
  for (unsigned int r = 0; r < B.m(); ++r)
    for (unsigned int c = 0; c < B.n(); ++c) Bs(r, c) = B(r, c) * D[c] / s[r];
  return Bs;
}

/// x = -B^+ r: the minimum-norm least-squares step (SVD; singular values below 1e-10 of the
/// largest are left out).
Vector<double> pseudo_inverse_step(const FullMatrix<double> &B, const Vector<double> &r)
{
  const unsigned int m = B.m(), n = B.n();
  Vector<double> x(n);
  if (m == 0 || n == 0) return x;
  LAPACKFullMatrix<double> A(m, n);
  A = B;
  A.compute_svd();
  const LAPACKFullMatrix<double> &U = A.get_svd_u(), &Vt = A.get_svd_vt();
  for (unsigned int i = 0; i < std::min(m, n); ++i)
    {
      const double sigma = A.singular_value(i);
      if (!(sigma > 1e-10 * A.singular_value(0))) continue;
      double c = 0;
      for (unsigned int k = 0; k < m; ++k) c += U(k, i) * r[k];
      for (unsigned int k = 0; k < n; ++k) x[k] -= Vt(i, k) * c / sigma;
    }
  return x;
}

double max_abs(const Vector<double> &v) { return v.size() ? v.linfty_norm() : 0.0; }

/// Gauss-Newton onto Phi(q, t0) = 0 (every equation), in the scaled coordinates; @p moved
/// receives the sum of the corrections (x~). False if it does not converge.
bool project(const System &system, const double t0, Vector<double> &y, const Vector<double> &D,
             const std::vector<double> &s, const RedundancySettings &settings, Vector<double> &moved)
{
  Vector<double> phi, phi_t;
  FullMatrix<double> B;
  moved.reinit(system.n_v());
  for (unsigned int it = 0; it <= settings.max_iterations; ++it)
    {
      system.constraints(t0, y, true, phi, B, phi_t);
      for (unsigned int r = 0; r < phi.size(); ++r) phi[r] /= s[r];
      if (max_abs(phi) <= settings.projection_tolerance) return true;
      if (it == settings.max_iterations || !std::isfinite(max_abs(phi))) break;
      const Vector<double> step = pseudo_inverse_step(scaled(B, D, s), phi);
      moved += step;
      Vector<double> dx(step);
      dx.scale(D);
      system.move_positions(y, dx);
    }
  return false;
}

/// The joints of the rows in @p dependent and of the independent rows they are combinations of
/// at the start (least squares over the independent rows of @p Bs): the loop that closes there.
std::string loop_joints(const System &system, const FullMatrix<double> &Bs, const std::vector<unsigned int> &dependent)
{
  const auto rows = system.constraint_rows(true);
  std::vector<unsigned int> independent;
  for (unsigned int r = 0; r < Bs.m(); ++r)
    if (std::find(dependent.begin(), dependent.end(), r) == dependent.end()) independent.push_back(r);
  // A^T c = b_d for the rows A of the independent equations (unique: they are independent).
  FullMatrix<double> At(Bs.n(), independent.size());
  for (unsigned int i = 0; i < independent.size(); ++i)
    for (unsigned int c = 0; c < Bs.n(); ++c) At(c, i) = Bs(independent[i], c);
  std::set<unsigned int> joints;
  for (const unsigned int d : dependent)
    {
      joints.insert(rows[d].first);
      Vector<double> b(Bs.n());
      for (unsigned int c = 0; c < Bs.n(); ++c) b[c] = -Bs(d, c);
      const Vector<double> coefficients = pseudo_inverse_step(At, b);
      const double largest = max_abs(coefficients);
      for (unsigned int i = 0; i < independent.size(); ++i)
        if (std::abs(coefficients[i]) > 1e-6 * largest) joints.insert(rows[independent[i]].first);
    }
  std::string names;
  for (const unsigned int j : joints) names += (names.empty() ? "'" : ", '") + system.joint(j).name() + "'";
  return names;
}

/// The InputError of a singular start: the joints of the loop, why, and what to change.
[[noreturn]] void refuse_singular_start(const System &system, const FullMatrix<double> &Bs,
                                        const std::vector<unsigned int> &dependent, const std::string &why)
{
  std::ostringstream s;
  s << "the start is a singular configuration (a dead point, or links in line) of the joints "
    << loop_joints(system, Bs, dependent) << ": " << why
    << "; an equation that depends on the others only there is not redundant (dropped, it would let the bodies "
       "leave the joint). Move the bodies' start positions away from the dead point or the collinear position";
  throw InputError("Multibody/Joints", s.str());
}
} // namespace

std::vector<unsigned int> dependent_rows(const FullMatrix<double> &B, const double rank_tolerance,
                                         std::vector<Vector<double>> *basis_out)
{
  std::vector<Vector<double>> basis;
  std::vector<unsigned int> dependent;
  for (unsigned int r = 0; r < B.m(); ++r)
    {
      Vector<double> w(B.n());
      for (unsigned int c = 0; c < B.n(); ++c) w[c] = B(r, c);
      const double norm = w.l2_norm();
      for (unsigned int pass = 0; pass < 2; ++pass)
        for (const auto &q : basis) w.add(-(q * w), q);
      if (norm == 0 || w.l2_norm() <= rank_tolerance * norm)
        dependent.push_back(r);
      else
        {
          w /= w.l2_norm();
          basis.push_back(w);
        }
    }
  if (basis_out) *basis_out = std::move(basis);
  return dependent;
}

double scene_length_scale(const System &system, const Vector<double> &y)
{
  double L = 0;
  FullMatrix<double> M;
  system.mass_matrix(y, M);
  std::vector<Vector3> origins(1); // the ground's
  for (unsigned int b = 1; b < system.n_bodies(); ++b)
    {
      const double *q = system.q_of(b, y);
      origins.push_back(Vector3({q[0], q[1], q[2]}));
      const unsigned int v = system.v_offset(b);
      const double m = M(v, v), J = M(v + 3, v + 3) + M(v + 4, v + 4) + M(v + 5, v + 5);
      if (m > 0) L = std::max(L, std::sqrt(J / (2 * m))); // J_O trace = 2 m r^2 for a point at r
    }
  for (unsigned int a = 0; a < origins.size(); ++a)
    for (unsigned int b = a + 1; b < origins.size(); ++b) L = std::max(L, (origins[a] - origins[b]).norm());
  return L > 0 && std::isfinite(L) ? L : 1.0;
}

RedundancyAnalysis find_redundant_equations(const System &system, const double t0, const Vector<double> &y0,
                                            const RedundancySettings &settings)
{
  RedundancyAnalysis result;
  const double L = result.length_scale = scene_length_scale(system, y0);
  const Vector<double> D = coordinate_scales(system, y0, L);
  const auto rows = system.constraint_rows(true);
  Vector<double> phi, phi_t;
  FullMatrix<double> B;
  system.constraints(t0, y0, true, phi, B, phi_t);

  // s_r: the norm of row r of B D (a row that vanishes takes the largest, not to divide by 0).
  std::vector<double> &s = result.equation_scales;
  s.assign(B.m(), 0.0);
  for (unsigned int r = 0; r < B.m(); ++r)
    for (unsigned int c = 0; c < B.n(); ++c) s[r] += std::pow(B(r, c) * D[c], 2);
  for (auto &x : s) x = std::sqrt(x);
  const double largest = s.empty() ? 1.0 : *std::max_element(s.begin(), s.end());
  for (auto &x : s)
    if (!(x > 1e-14 * largest)) x = largest > 0 ? largest : 1.0;

  const FullMatrix<double> B0 = scaled(B, D, s);
  std::vector<Vector<double>> row_space;
  const std::vector<unsigned int> dependent0 = dependent_rows(B0, settings.rank_tolerance, &row_space);
  if (dependent0.empty()) return result; // full row rank: a regular start, nothing to drop

  // Configurations nearby: random directions (fixed seed: the same scene gives the same answer)
  // in the null space of B~ (orthogonal to its row space), a step of settings.step each.
  std::mt19937 random(20231123);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::vector<unsigned int> dependent_nearby;
  for (unsigned int k = 0; k < settings.neighbours; ++k)
    {
      Vector<double> u(system.n_v());
      for (auto &x : u) x = uniform(random);
      const double norm = u.l2_norm();
      for (unsigned int pass = 0; pass < 2; ++pass)
        for (const auto &q : row_space) u.add(-(q * u), q);
      // No first-order motion: the start is an isolated solution of full column rank (a
      // mechanism held by drivers), regular; the rows that depend there depend nearby too.
      if (u.l2_norm() <= 1e-8 * norm) break;
      u *= settings.step / u.l2_norm();
      Vector<double> y(y0), dx(u), moved;
      dx.scale(D);
      system.move_positions(y, dx);
      std::ostringstream distance;
      distance << std::setprecision(3) << settings.step * L << " m";
      if (!project(system, t0, y, D, s, settings, moved) || moved.l2_norm() > settings.return_limit * settings.step)
        refuse_singular_start(system, B0, dependent0,
                              "they allow a motion there to first order that they do not allow " + distance.str() +
                                " on (the mechanism is locked there)");
      system.constraints(t0, y, true, phi, B, phi_t);
      const std::vector<unsigned int> dependent = dependent_rows(scaled(B, D, s), settings.rank_tolerance);
      if (dependent.size() != dependent0.size() || (k > 0 && dependent != dependent_nearby))
        {
          std::vector<unsigned int> both(dependent0);
          for (const unsigned int r : dependent)
            if (std::find(both.begin(), both.end(), r) == both.end()) both.push_back(r);
          refuse_singular_start(system, B0, both,
                                std::to_string(dependent0.size()) + " of their equations depend on the others at the start, " +
                                  std::to_string(dependent.size()) + " at an assembled configuration " + distance.str() + " away");
        }
      dependent_nearby = dependent;
      ++result.neighbours_checked;
    }
  if (result.neighbours_checked == 0) dependent_nearby = dependent0;

  // The rows nearby are those to drop; where the start is special for the choice of rows only
  // (same rank, other rows), the rows kept must still be independent at the start.
  if (dependent_nearby != dependent0)
    {
      FullMatrix<double> kept(B0.m() - dependent_nearby.size(), B0.n());
      for (unsigned int r = 0, i = 0; r < B0.m(); ++r)
        if (std::find(dependent_nearby.begin(), dependent_nearby.end(), r) == dependent_nearby.end())
          {
            for (unsigned int c = 0; c < B0.n(); ++c) kept(i, c) = B0(r, c);
            ++i;
          }
      if (!dependent_rows(kept, settings.rank_tolerance).empty())
        refuse_singular_start(system, B0, dependent0,
                              "the equations that depend on the others at the start are not those that do nearby");
    }
  for (const unsigned int r : dependent_nearby) result.redundant.push_back(rows[r]);
  return result;
}
} // namespace flextrack::multibody
