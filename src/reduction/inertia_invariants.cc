#include <geometry/rotation.h>
#include <reduction/inertia_invariants.h>

#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/lapack_templates.h>

#include <algorithm>
#include <array>
#include <atomic>

namespace flextrack::reduction
{
using namespace dealii;

using geometry::skew;

namespace
{
std::atomic<unsigned long long> next_id{1};
}

Point<3> InertiaInvariants::centre_of_mass() const { return Point<3>(first_moment / mass); }

Tensor<2, 3> InertiaInvariants::inertia_about_centre_of_mass() const
{
  const Tensor<1, 3> c = first_moment / mass;
  return inertia_origin - mass * ((c * c) * unit_symmetric_tensor<3>() - outer_product(c, c));
}

Tensor<1, 3> InertiaInvariants::I5(const unsigned int j, const unsigned int k) const
{
  const Tensor<2, 3> &q = Q[j * n_modes() + k];
  return Tensor<1, 3>({q[1][2] - q[2][1], q[2][0] - q[0][2], q[0][1] - q[1][0]});
}

FloatingFrameInertia::FloatingFrameInertia(const InertiaInvariants &invariants, const FullMatrix<double> &modal_mass)
  : n(invariants.n_modes()), id(next_id++), inv(invariants), modal_mass(modal_mass), i5(n * n), q_rows(9 * n * n),
    i5_rows(3 * n * n)
{
  for (unsigned int j = 0; j < n; ++j)
    for (unsigned int k = 0; k < n; ++k)
      {
        i5[j * n + k] = inv.I5(j, k);
        for (unsigned int a = 0; a < 3; ++a)
          {
            i5_rows[(3 * k + a) * n + j] = i5[j * n + k][a];
            for (unsigned int b = 0; b < 3; ++b) q_rows[(9 * k + 3 * a + b) * n + j] = inv.Q[k * n + j][a][b];
          }
      }
}

namespace
{
/// y = R x for the row-major (rows x n) array @p R: BLAS' dgemv on its column-major transpose.
/// A 32-mode body's eta sums (12 n^2 products per residual) were 8 % of the laser robot's
/// instructions as scalar dot products, which the compiler may not vectorise (it may not reorder
/// a floating-point sum).
void rows_times(const std::vector<double> &R, const unsigned int rows, const unsigned int n, const double *x, double *y)
{
  if (n == 0 || rows == 0) return; // BLAS refuses a leading dimension of 0
  const types::blas_int m = n, columns = rows, one = 1;
  const double unit = 1, zero = 0;
  gemv("T", &m, &columns, &unit, R.data(), &m, x, &one, &zero, y, &one);
}
} // namespace

const FloatingFrameInertia::EtaTerms &FloatingFrameInertia::eta_terms(const double *eta) const
{
  struct Entry
  {
    unsigned long long owner = 0;
    std::vector<double> eta;
    EtaTerms terms;
  };
  // A rigid body's terms are its constants: formed in place, they take no place in the cache.
  if (n == 0)
    {
      thread_local EtaTerms rigid;
      rigid.S = inv.first_moment;
      rigid.J = inv.inertia_origin;
      rigid.Ph.clear();
      rigid.Mwf.clear();
      return rigid;
    }
  // A few flexible inertias per thread (one per body that a residual visits in turn); the
  // oldest goes.
  thread_local std::array<Entry, 8> cache;
  thread_local unsigned int next = 0;
  for (Entry &e : cache)
    if (e.owner == id && e.eta.size() == n && std::equal(e.eta.begin(), e.eta.end(), eta)) return e.terms;
  Entry *slot = nullptr;
  for (Entry &e : cache)
    if (e.owner == id) slot = &e; // this inertia's own entry, at another eta
  if (!slot) slot = &cache[next++ % cache.size()];
  slot->owner = 0; // the key is written last: a throw below (bad_alloc) leaves no stale entry
  slot->eta.assign(eta, eta + n);
  EtaTerms &t = slot->terms;
  t.Ph.resize(n);
  t.Mwf.resize(n);
  t.S = inv.first_moment;
  thread_local std::vector<double> q_eta, i5_eta; // sum_j eta_j Q_kj[a][b] and sum_j eta_j I5_jk[a]
  q_eta.resize(9 * n);
  i5_eta.resize(3 * n);
  rows_times(q_rows, 9 * n, n, eta, q_eta.data());
  rows_times(i5_rows, 3 * n, n, eta, i5_eta.data());
  Tensor<2, 3> Pe, Qee;
  for (unsigned int k = 0; k < n; ++k)
    {
      for (unsigned int a = 0; a < 3; ++a)
        {
          t.S[a] += inv.I3(a, k) * eta[k];
          t.Mwf[k][a] = inv.I4(a, k) + i5_eta[3 * k + a];
          for (unsigned int b = 0; b < 3; ++b) t.Ph[k][a][b] = inv.P[k][a][b] + q_eta[9 * k + 3 * a + b];
        }
      Pe += eta[k] * inv.P[k];
    }
  for (unsigned int k = 0; k < n; ++k) Qee += eta[k] * (t.Ph[k] - inv.P[k]); // sum_jk eta_j eta_k Q_kj
  t.J = inv.inertia_origin + (2 * trace(Pe) + trace(Qee)) * unit_symmetric_tensor<3>() - Pe - transpose(Pe) - Qee;
  slot->owner = id;
  return t;
}

void FloatingFrameInertia::mass_matrix(const Tensor<2, 3> &A, const double *eta, FullMatrix<double> &M) const
{
  M.reinit(6 + n, 6 + n);
  const EtaTerms &t = eta_terms(eta);
  const Tensor<2, 3> MRw = -A * skew(t.S);
  for (unsigned int a = 0; a < 3; ++a)
    {
      M(a, a) = inv.mass;
      for (unsigned int b = 0; b < 3; ++b)
        {
          M(a, 3 + b) = M(3 + b, a) = MRw[a][b];
          M(3 + a, 3 + b) = t.J[a][b];
        }
    }
  for (unsigned int k = 0; k < n; ++k)
    {
      Tensor<1, 3> AI3; // A I3_k
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int b = 0; b < 3; ++b) AI3[a] += A[a][b] * inv.I3(b, k);
      for (unsigned int a = 0; a < 3; ++a)
        {
          M(a, 6 + k) = M(6 + k, a) = AI3[a];
          M(3 + a, 6 + k) = M(6 + k, 3 + a) = t.Mwf[k][a];
        }
      for (unsigned int j = 0; j < n; ++j) M(6 + j, 6 + k) = modal_mass(j, k);
    }
}

void FloatingFrameInertia::mass_times(const Tensor<2, 3> &A, const double *eta, const double *v_dot,
                                      double *Mv) const
{
  // The rows of mass_matrix() times (R'', omega', eta''): M_Rw omega' = -A (S x omega'),
  // M_wR R'' = S x (A^T R''), M_fR R'' = I3_k . (A^T R'').
  const EtaTerms &t = eta_terms(eta);
  const Tensor<1, 3> a({v_dot[0], v_dot[1], v_dot[2]}), alpha({v_dot[3], v_dot[4], v_dot[5]});
  const Tensor<1, 3> a_body = transpose(A) * a;
  Tensor<1, 3> h = -cross_product_3d(t.S, alpha), r_w = cross_product_3d(t.S, a_body) + t.J * alpha;
  for (unsigned int k = 0; k < n; ++k)
    {
      const double edd = v_dot[6 + k];
      double r_k = t.Mwf[k] * alpha;
      for (unsigned int b = 0; b < 3; ++b)
        {
          h[b] += inv.I3(b, k) * edd;
          r_k += inv.I3(b, k) * a_body[b];
        }
      r_w += edd * t.Mwf[k];
      for (unsigned int j = 0; j < n; ++j) r_k += modal_mass(k, j) * v_dot[6 + j];
      Mv[6 + k] = r_k;
    }
  const Tensor<1, 3> r_R = inv.mass * a + A * h;
  for (unsigned int b = 0; b < 3; ++b)
    {
      Mv[b] = r_R[b];
      Mv[3 + b] = r_w[b];
    }
}

void FloatingFrameInertia::quadratic_velocity(const Tensor<2, 3> &A, const double *eta, const Tensor<1, 3> &w,
                                              const double *eta_dot,
                                              Vector<double> &Qv) const
{
  Qv.reinit(6 + n);
  const EtaTerms &t = eta_terms(eta);
  Tensor<1, 3> I3ed; // I3 etad
  for (unsigned int k = 0; k < n; ++k)
    for (unsigned int a = 0; a < 3; ++a) I3ed[a] += inv.I3(a, k) * eta_dot[k];
  const Tensor<1, 3> QR = -(A * (cross_product_3d(w, cross_product_3d(w, t.S)) + 2 * cross_product_3d(w, I3ed)));
  Tensor<1, 3> Qw = -cross_product_3d(w, t.J * w);
  for (unsigned int k = 0; k < n; ++k) Qw -= 2 * eta_dot[k] * (trace(t.Ph[k]) * w - t.Ph[k] * w);
  for (unsigned int a = 0; a < 3; ++a)
    {
      Qv[a] = QR[a];
      Qv[3 + a] = Qw[a];
    }
  const double w2 = w * w;
  thread_local std::vector<double> coriolis; // sum_j etad_j I5_jk[a] at 3 k + a
  coriolis.resize(3 * n);
  rows_times(i5_rows, 3 * n, n, eta_dot, coriolis.data());
  for (unsigned int k = 0; k < n; ++k)
    {
      const Tensor<1, 3> c_k({coriolis[3 * k], coriolis[3 * k + 1], coriolis[3 * k + 2]});
      Qv[6 + k] = -(w * (t.Ph[k] * w) - w2 * trace(t.Ph[k]) + 2 * (w * c_k));
    }
}
} // namespace flextrack::reduction
