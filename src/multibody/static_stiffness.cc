// The residual of static equilibrium and its tangent (static_stiffness.h).
#include <multibody/static_stiffness.h>

#include <Epetra_CrsMatrix.h>

namespace flextrack::multibody
{
using namespace dealii;

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

void velocity_row_tangents(System &system, const double t, const Vector<double> &y, const Vector<double> &yp,
                           FullMatrix<double> &K, FullMatrix<double> *C)
{
  const unsigned int nq = system.n_q(), nv = system.n_v();
  system.use_newton_matrix(false); // the exact tangent
  system.assemble_jacobian(t, 0.0, y, yp);
  const Epetra_CrsMatrix &J = system.jacobian();
  // dF_v / dq and dF_v / dv, dense: a body's rows are dense in its own columns anyway.
  FullMatrix<double> J_vq(nv, nq);
  if (C) C->reinit(nv, nv);
  for (unsigned int i = 0; i < nv; ++i)
    {
      int n_entries = 0;
      double *values = nullptr;
      int *columns = nullptr;
      J.ExtractMyRowView(nq + i, n_entries, values, columns); // serial map: local = global
      for (int e = 0; e < n_entries; ++e)
        {
          const unsigned int c = columns[e];
          if (c < nq) J_vq(i, c) = values[e];
          else if (C && c < nq + nv) (*C)(i, c - nq) = values[e];
        }
    }
  // Column c of T(q): the coordinate rates of the unit velocity e_c (at most four entries).
  K.reinit(nv, nv);
  Vector<double> unit(system.size()), q_dot;
  for (unsigned int i = 0; i < nq; ++i) unit[i] = y[i];
  std::vector<unsigned int> touched;
  for (unsigned int c = 0; c < nv; ++c)
    {
      unit[nq + c] = 1;
      system.coordinate_rates(unit, q_dot);
      unit[nq + c] = 0;
      touched.clear();
      for (unsigned int k = 0; k < nq; ++k)
        if (q_dot[k] != 0) touched.push_back(k);
      for (unsigned int i = 0; i < nv; ++i)
        {
          double sum = 0;
          for (const unsigned int k : touched) sum += J_vq(i, k) * q_dot[k];
          K(i, c) = sum;
        }
    }
}

void static_stiffness(System &system, const double t0, const Vector<double> &y, const Vector<double> &lambda,
                      FullMatrix<double> &K, FullMatrix<double> &B)
{
  const unsigned int nq = system.n_q(), nv = system.n_v(), nl = system.n_lambda();
  Vector<double> phi, phi_t;
  system.constraints(t0, y, false, phi, B, phi_t);
  // The DAE state at rest: positions of y, v = 0, lambda, and mu = 0 (mu only enters the
  // position rows, which are not used); y' = 0 and alpha = 0, so no mass term.
  Vector<double> state(system.size()), rate(system.size());
  for (unsigned int i = 0; i < nq; ++i) state[i] = y[i];
  for (unsigned int k = 0; k < nl; ++k) state[nq + nv + k] = lambda[k];
  velocity_row_tangents(system, t0, state, rate, K, nullptr);
}

void static_stiffness_by_differences(const System &system, const double t0, const Vector<double> &y,
                                     const Vector<double> &lambda, const double h, FullMatrix<double> &K,
                                     FullMatrix<double> &B)
{
  const unsigned int nv = system.n_v();
  Vector<double> phi, phi_t, r_plus, r_minus;
  system.constraints(t0, y, false, phi, B, phi_t);
  K.reinit(nv, nv);
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
} // namespace flextrack::multibody
