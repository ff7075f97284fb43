#include <geometry/rotation.h>
#include <reduction/inertia_invariants_builder.h>

#include <deal.II/lac/lapack_full_matrix.h>

namespace flextrack::reduction
{
using namespace dealii;

InertiaInvariants compute_inertia_invariants(const fem::BodyModel &body, const std::vector<Vector<double>> &modes)
{
  std::vector<Vector<double>> full;
  for (const auto &phi : modes) full.push_back(body.expand(phi));
  return compute_inertia_invariants_of_expanded(body, full);
}

InertiaInvariants compute_inertia_invariants_of_expanded(const fem::BodyModel &body, const std::vector<Vector<double>> &full)
{
  const auto &nodes = body.full_nodes();
  const unsigned int n = full.size(), N = nodes.size(), n_full = body.n_full_dofs();

  // Scalar fields at the nodes: 1, x, y, z, then phi_k,a. All scalar products int rho f g use
  // the x-displacement block of the mass matrix (every block of the translations is the same).
  const unsigned int n_fields = 4 + 3 * n;
  LAPACKFullMatrix<double> F(N, n_fields), MF(N, n_fields);
  for (unsigned int i = 0; i < N; ++i)
    {
      F(i, 0) = 1;
      for (unsigned int b = 0; b < 3; ++b) F(i, 1 + b) = nodes[i].x[b];
      for (unsigned int k = 0; k < n; ++k)
        for (unsigned int a = 0; a < 3; ++a) F(i, 4 + 3 * k + a) = full[k][nodes[i].u[a]];
    }
  // M times the fields, in blocks of columns (one pass over the matrices per block).
  const unsigned int block = 32;
  std::vector<double> X(static_cast<std::size_t>(n_full) * block), Y(X.size());
  for (unsigned int first = 0; first < n_fields; first += block)
    {
      const unsigned int m = std::min(block, n_fields - first);
      std::fill(X.begin(), X.end(), 0.0);
      for (unsigned int f = 0; f < m; ++f)
        for (unsigned int i = 0; i < N; ++i) X[static_cast<std::size_t>(f) * n_full + nodes[i].u[0]] = F(i, first + f);
      body.full_mass_multiply(X.data(), m, Y.data());
      for (unsigned int f = 0; f < m; ++f)
        for (unsigned int i = 0; i < N; ++i) MF(i, first + f) = Y[static_cast<std::size_t>(f) * n_full + nodes[i].u[0]];
    }
  Vector<double> field(n_full), Mfield(n_full);
  LAPACKFullMatrix<double> C(n_fields, n_fields);
  F.Tmmult(C, MF);

  InertiaInvariants inv;
  inv.mass = C(0, 0);
  Tensor<2, 3> X2;
  for (unsigned int a = 0; a < 3; ++a)
    {
      inv.first_moment[a] = C(0, 1 + a);
      for (unsigned int b = 0; b < 3; ++b) X2[a][b] = C(1 + a, 1 + b);
    }
  inv.inertia_origin = trace(X2) * unit_symmetric_tensor<3>() - X2;
  inv.I3.reinit(3, n);
  inv.I4.reinit(3, n);
  inv.P.resize(n);
  inv.Q.resize(n * n);
  for (unsigned int k = 0; k < n; ++k)
    for (unsigned int a = 0; a < 3; ++a)
      {
        inv.I3(a, k) = C(0, 4 + 3 * k + a);
        for (unsigned int b = 0; b < 3; ++b)
          {
            inv.P[k][a][b] = C(4 + 3 * k + a, 1 + b);
            for (unsigned int j = 0; j < n; ++j) inv.Q[j * n + k][b][a] = C(4 + 3 * j + b, 4 + 3 * k + a);
          }
      }
  for (unsigned int k = 0; k < n; ++k)
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = 0; b < 3; ++b)
        for (unsigned int c = 0; c < 3; ++c)
          if (const double e = geometry::levi_civita(a, b, c); e != 0) inv.I4(a, k) += e * inv.P[k][c][b];

  // Rotary inertia of arm sections and point masses: the rotation dofs turn by e_a.
  bool has_rotations = false;
  for (const auto &node : nodes) has_rotations |= node.theta[0] >= 0;
  if (has_rotations)
    for (unsigned int a = 0; a < 3; ++a)
      {
        field = 0;
        for (const auto &node : nodes)
          if (node.theta[a] >= 0) field[node.theta[a]] = 1;
        body.full_mass_vmult(Mfield, field);
        for (unsigned int b = 0; b < 3; ++b)
          {
            double J = 0;
            for (const auto &node : nodes)
              if (node.theta[b] >= 0) J += Mfield[node.theta[b]];
            inv.inertia_origin[b][a] += J;
          }
        for (unsigned int k = 0; k < n; ++k) inv.I4(a, k) += full[k] * Mfield;
      }
  return inv;
}
} // namespace flextrack::reduction
