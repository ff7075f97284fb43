#include <fem/fe_serendipity.h>

#include <deal.II/base/geometry_info.h>
#include <deal.II/fe/fe_data.h>

namespace flextrack::fem
{
using namespace dealii;

std::array<Point<3>, 20> SerendipityPolynomials::nodes()
{
  std::array<Point<3>, 20> x;
  for (unsigned int v = 0; v < 8; ++v) x[v] = GeometryInfo<3>::unit_cell_vertex(v);
  for (unsigned int l = 0; l < 12; ++l)
    x[8 + l] = 0.5 * (GeometryInfo<3>::unit_cell_vertex(GeometryInfo<3>::line_to_cell_vertices(l, 0)) +
                      GeometryInfo<3>::unit_cell_vertex(GeometryInfo<3>::line_to_cell_vertices(l, 1)));
  return x;
}

namespace
{
using Poly1 = std::array<double, 3>; // c0 + c1 t + c2 t^2
using Coefficients = std::array<std::array<std::array<double, 3>, 3>, 3>;

/// Product of three 1D factors f(xi) g(eta) h(zeta) as 3D coefficients.
Coefficients outer(const Poly1 &f, const Poly1 &g, const Poly1 &h)
{
  Coefficients c{};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int d = 0; d < 3; ++d) c[a][b][d] = f[a] * g[b] * h[d];
  return c;
}
} // namespace

SerendipityPolynomials::SerendipityPolynomials() : ScalarPolynomialsBase<3>(2, 20)
{
  const auto x = nodes();
  for (unsigned int i = 0; i < 20; ++i)
    {
      const double xi = 2 * x[i][0] - 1, eta = 2 * x[i][1] - 1, zeta = 2 * x[i][2] - 1;
      Coefficients &c = coefficients[i];
      if (i < 8)
        {
          // (1 + xi xi_i)(1 + eta eta_i)(1 + zeta zeta_i)(xi xi_i + eta eta_i + zeta zeta_i - 2) / 8:
          // multiply out the last factor term by term (xi_i^2 = 1).
          const Poly1 fx = {{1, xi, 0}}, fy = {{1, eta, 0}}, fz = {{1, zeta, 0}};
          const Coefficients base = outer(fx, fy, fz);
          c = {};
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
              for (int d = 0; d < 3; ++d)
                {
                  const double v = base[a][b][d] / 8;
                  if (v == 0) continue;
                  c[a][b][d] += -2 * v;
                  c[a + 1][b][d] += xi * v; // a + 1 <= 2 since base has degree <= 1 per variable
                  c[a][b + 1][d] += eta * v;
                  c[a][b][d + 1] += zeta * v;
                }
        }
      else
        {
          const Poly1 bubble = {{1, 0, -1}};
          const Poly1 fx = xi == 0 ? bubble : Poly1{{1, xi, 0}};
          const Poly1 fy = eta == 0 ? bubble : Poly1{{1, eta, 0}};
          const Poly1 fz = zeta == 0 ? bubble : Poly1{{1, zeta, 0}};
          c = outer(fx, fy, fz);
          for (auto &plane : c)
            for (auto &row : plane)
              for (auto &v : row) v /= 4;
        }
    }
}

double SerendipityPolynomials::derivative(const unsigned int i, const Point<3> &p, const unsigned int dx,
                                          const unsigned int dy, const unsigned int dz) const
{
  // In xi = 2x - 1: d/dx = 2 d/dxi. Differentiate monomials xi^a -> a xi^(a-1).
  const double t[3] = {2 * p[0] - 1, 2 * p[1] - 1, 2 * p[2] - 1};
  auto term = [](const double v, const unsigned int power, const unsigned int order) {
    if (order > power) return 0.0;
    double factor = 1;
    for (unsigned int k = 0; k < order; ++k) factor *= (power - k);
    return factor * std::pow(v, static_cast<int>(power - order));
  };
  double sum = 0;
  const Coefficients &c = coefficients[i];
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int b = 0; b < 3; ++b)
      for (unsigned int d = 0; d < 3; ++d)
        if (c[a][b][d] != 0)
          sum += c[a][b][d] * term(t[0], a, dx) * term(t[1], b, dy) * term(t[2], d, dz);
  return sum * std::pow(2.0, static_cast<int>(dx + dy + dz));
}

double SerendipityPolynomials::compute_value(const unsigned int i, const Point<3> &p) const
{
  return derivative(i, p, 0, 0, 0);
}

Tensor<1, 3> SerendipityPolynomials::compute_1st_derivative(const unsigned int i, const Point<3> &p) const
{
  Tensor<1, 3> g;
  for (unsigned int a = 0; a < 3; ++a) g[a] = derivative(i, p, a == 0, a == 1, a == 2);
  return g;
}

Tensor<2, 3> SerendipityPolynomials::compute_2nd_derivative(const unsigned int i, const Point<3> &p) const
{
  Tensor<2, 3> h;
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int b = 0; b < 3; ++b)
      h[a][b] = derivative(i, p, (a == 0) + (b == 0), (a == 1) + (b == 1), (a == 2) + (b == 2));
  return h;
}

Tensor<3, 3> SerendipityPolynomials::compute_3rd_derivative(const unsigned int i, const Point<3> &p) const
{
  Tensor<3, 3> h;
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int b = 0; b < 3; ++b)
      for (unsigned int c = 0; c < 3; ++c)
        h[a][b][c] = derivative(i, p, (a == 0) + (b == 0) + (c == 0), (a == 1) + (b == 1) + (c == 1),
                                (a == 2) + (b == 2) + (c == 2));
  return h;
}

Tensor<4, 3> SerendipityPolynomials::compute_4th_derivative(const unsigned int i, const Point<3> &p) const
{
  Tensor<4, 3> h;
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int b = 0; b < 3; ++b)
      for (unsigned int c = 0; c < 3; ++c)
        for (unsigned int d = 0; d < 3; ++d)
          h[a][b][c][d] = derivative(i, p, (a == 0) + (b == 0) + (c == 0) + (d == 0),
                                     (a == 1) + (b == 1) + (c == 1) + (d == 1),
                                     (a == 2) + (b == 2) + (c == 2) + (d == 2));
  return h;
}

Tensor<1, 3> SerendipityPolynomials::compute_grad(const unsigned int i, const Point<3> &p) const
{
  return compute_1st_derivative(i, p);
}

Tensor<2, 3> SerendipityPolynomials::compute_grad_grad(const unsigned int i, const Point<3> &p) const
{
  return compute_2nd_derivative(i, p);
}

void SerendipityPolynomials::evaluate(const Point<3> &p, std::vector<double> &values,
                                      std::vector<Tensor<1, 3>> &grads, std::vector<Tensor<2, 3>> &grad_grads,
                                      std::vector<Tensor<3, 3>> &third, std::vector<Tensor<4, 3>> &fourth) const
{
  for (unsigned int i = 0; i < 20; ++i)
    {
      if (!values.empty()) values[i] = compute_value(i, p);
      if (!grads.empty()) grads[i] = compute_1st_derivative(i, p);
      if (!grad_grads.empty()) grad_grads[i] = compute_2nd_derivative(i, p);
      if (!third.empty()) third[i] = compute_3rd_derivative(i, p);
      if (!fourth.empty()) fourth[i] = compute_4th_derivative(i, p);
    }
}

std::unique_ptr<ScalarPolynomialsBase<3>> SerendipityPolynomials::clone() const
{
  return std::make_unique<SerendipityPolynomials>(*this);
}

FE_Serendipity<3>::FE_Serendipity()
  : FE_Poly<3>(SerendipityPolynomials(), FiniteElementData<3>({1, 1, 0, 0}, 1, 2, FiniteElementData<3>::H1),
               std::vector<bool>(20, false), std::vector<ComponentMask>(20, ComponentMask(1, true)))
{
  const auto x = SerendipityPolynomials::nodes();
  unit_support_points.assign(x.begin(), x.end());
  // The serendipity quad on a face: 4 vertices, then the midpoints of its 4 lines in deal.II's
  // line order (x = 0, x = 1, y = 0, y = 1); FESystem needs these.
  std::vector<Point<2>> face;
  for (unsigned int v = 0; v < 4; ++v) face.push_back(GeometryInfo<2>::unit_cell_vertex(v));
  for (unsigned int l = 0; l < 4; ++l)
    face.push_back(0.5 * (GeometryInfo<2>::unit_cell_vertex(GeometryInfo<2>::line_to_cell_vertices(l, 0)) +
                          GeometryInfo<2>::unit_cell_vertex(GeometryInfo<2>::line_to_cell_vertices(l, 1))));
  unit_face_support_points[0] = face;
}

std::unique_ptr<FiniteElement<3, 3>> FE_Serendipity<3>::clone() const
{
  return std::make_unique<FE_Serendipity<3>>(*this);
}

void FE_Serendipity<3>::convert_generalized_support_point_values_to_dof_values(
  const std::vector<Vector<double>> &support_point_values, std::vector<double> &nodal_values) const
{
  // A nodal (Lagrange-type) element: the dof values are the values at the nodes.
  for (unsigned int i = 0; i < 20; ++i) nodal_values[i] = support_point_values[i](0);
}
} // namespace flextrack::fem
