// Stresses of a solid's displacement field (issue 12): the isotropic linear elastic law
// sigma = lambda tr(eps) 1 + 2 mu eps, eps = sym(grad u), and the fields 'flextrack static'
// draws: the stress components, von Mises' equivalent stress and the principal stresses.
#pragma once

#include <fem/material.h>

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <array>

namespace flextrack::fem
{
/// sigma [Pa] of the displacement gradient @p grad_u for @p material.
dealii::SymmetricTensor<2, 3> stress(const Material &material, const dealii::Tensor<2, 3> &grad_u);
/// sqrt(3/2 s:s), s the deviator of @p sigma [Pa].
double von_mises(const dealii::SymmetricTensor<2, 3> &sigma);
/// Principal stresses, largest first [Pa].
std::array<double, 3> principal_stresses(const dealii::SymmetricTensor<2, 3> &sigma);

/// For deal.II's DataOut on a displacement field (3 components): stress_xx, stress_yy,
/// stress_zz, stress_xy, stress_yz, stress_xz, von_mises, principal_1 >= principal_2 >=
/// principal_3 [Pa], evaluated at the output points of each cell (not averaged across cells).
class StressPostprocessor : public dealii::DataPostprocessor<3>
{
public:
  explicit StressPostprocessor(const Material &material) : material(material) {}
  void evaluate_vector_field(const dealii::DataPostprocessorInputs::Vector<3> &inputs,
                             std::vector<dealii::Vector<double>> &computed) const override;
  std::vector<std::string> get_names() const override;
  dealii::UpdateFlags get_needed_update_flags() const override { return dealii::update_gradients; }

private:
  Material material;
};
} // namespace flextrack::fem
