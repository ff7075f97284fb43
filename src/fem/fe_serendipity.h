// The 20-node serendipity hexahedron (seed eq. 30) as a deal.II finite element.
//
// deal.II 9.4 has no serendipity element. This one is an FE_Poly over the 20 serendipity shape
// functions on the unit cube [0,1]^3, written with xi = 2x - 1 etc. in [-1, 1]:
//   corner node (xi_i, eta_i, zeta_i in {-1, 1}):
//     N = (1 + xi xi_i)(1 + eta eta_i)(1 + zeta zeta_i)(xi xi_i + eta eta_i + zeta zeta_i - 2) / 8
//   mid-edge node with xi_i = 0 (similarly for eta, zeta):
//     N = (1 - xi^2)(1 + eta eta_i)(1 + zeta zeta_i) / 4
// Degrees of freedom: one per vertex (deal.II's vertex order) and one per line (deal.II's line
// order), none on faces or inside. With one dof per line, neighbouring cells agree whatever the
// orientation of their shared faces, so the element is H1-conforming on any hex mesh.
// The space holds all quadratics and x^2 y-type cubics, but not the full triquadratic space.
#pragma once

#include <deal.II/base/scalar_polynomials_base.h>
#include <deal.II/fe/fe_poly.h>

#include <array>

namespace flextrack::fem
{
/// The 20 serendipity polynomials, each stored by its coefficients c[a][b][g] of
/// xi^a eta^b zeta^g (a, b, g <= 2), evaluated with any derivative order.
class SerendipityPolynomials : public dealii::ScalarPolynomialsBase<3>
{
public:
  SerendipityPolynomials();

  void evaluate(const dealii::Point<3> &unit_point, std::vector<double> &values,
                std::vector<dealii::Tensor<1, 3>> &grads, std::vector<dealii::Tensor<2, 3>> &grad_grads,
                std::vector<dealii::Tensor<3, 3>> &third_derivatives,
                std::vector<dealii::Tensor<4, 3>> &fourth_derivatives) const override;
  double compute_value(unsigned int i, const dealii::Point<3> &p) const override;
  dealii::Tensor<1, 3> compute_1st_derivative(unsigned int i, const dealii::Point<3> &p) const override;
  dealii::Tensor<2, 3> compute_2nd_derivative(unsigned int i, const dealii::Point<3> &p) const override;
  dealii::Tensor<3, 3> compute_3rd_derivative(unsigned int i, const dealii::Point<3> &p) const override;
  dealii::Tensor<4, 3> compute_4th_derivative(unsigned int i, const dealii::Point<3> &p) const override;
  dealii::Tensor<1, 3> compute_grad(unsigned int i, const dealii::Point<3> &p) const override;
  dealii::Tensor<2, 3> compute_grad_grad(unsigned int i, const dealii::Point<3> &p) const override;
  std::string name() const override { return "SerendipityPolynomials"; }
  std::unique_ptr<dealii::ScalarPolynomialsBase<3>> clone() const override;

  /// The 20 nodes on the unit cube, in dof order (8 vertices, then 12 line midpoints).
  static std::array<dealii::Point<3>, 20> nodes();

private:
  using Coefficients = std::array<std::array<std::array<double, 3>, 3>, 3>;
  /// d^{dx+dy+dz} N_i / dx^dx dy^dy dz^dz on the unit cube.
  double derivative(unsigned int i, const dealii::Point<3> &p, unsigned int dx, unsigned int dy,
                    unsigned int dz) const;
  std::array<Coefficients, 20> coefficients;
};

template <int dim>
class FE_Serendipity;

template <>
class FE_Serendipity<3> : public dealii::FE_Poly<3>
{
public:
  FE_Serendipity();
  std::string get_name() const override { return "FE_Serendipity<3>()"; }
  std::unique_ptr<dealii::FiniteElement<3, 3>> clone() const override;
  void convert_generalized_support_point_values_to_dof_values(
    const std::vector<dealii::Vector<double>> &support_point_values,
    std::vector<double> &nodal_values) const override;
};
} // namespace flextrack::fem
