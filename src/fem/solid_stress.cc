#include <fem/solid_stress.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace flextrack::fem
{
using namespace dealii;

SymmetricTensor<2, 3> stress(const Material &material, const Tensor<2, 3> &grad_u)
{
  const double E = material.youngs_modulus, nu = material.poisson_ratio;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const SymmetricTensor<2, 3> eps = symmetrize(grad_u);
  return lambda * trace(eps) * unit_symmetric_tensor<3>() + 2 * mu * eps;
}

double von_mises(const SymmetricTensor<2, 3> &sigma)
{
  const SymmetricTensor<2, 3> s = deviator(sigma);
  return std::sqrt(1.5 * (s * s));
}

std::array<double, 3> principal_stresses(const SymmetricTensor<2, 3> &sigma)
{
  // deal.II's eigenvalues() of a symmetric 3x3 tensor come sorted in descending order.
  const auto e = eigenvalues(sigma);
  std::array<double, 3> p = {{e[0], e[1], e[2]}};
  std::sort(p.begin(), p.end(), std::greater<>());
  return p;
}

void StressPostprocessor::evaluate_vector_field(const DataPostprocessorInputs::Vector<3> &inputs,
                                                std::vector<Vector<double>> &computed) const
{
  for (std::size_t q = 0; q < inputs.solution_gradients.size(); ++q)
    {
      Tensor<2, 3> grad;
      for (unsigned int c = 0; c < 3; ++c) grad[c] = inputs.solution_gradients[q][c];
      const auto sigma = stress(material, grad);
      const auto p = principal_stresses(sigma);
      auto &out = computed[q];
      out[0] = sigma[0][0];
      out[1] = sigma[1][1];
      out[2] = sigma[2][2];
      out[3] = sigma[0][1];
      out[4] = sigma[1][2];
      out[5] = sigma[0][2];
      out[6] = von_mises(sigma);
      for (unsigned int k = 0; k < 3; ++k) out[7 + k] = p[k];
    }
}

std::vector<std::string> StressPostprocessor::get_names() const
{
  return {"stress_xx", "stress_yy", "stress_zz", "stress_xy", "stress_yz", "stress_xz",
          "von_mises", "principal_1", "principal_2", "principal_3"};
}
} // namespace flextrack::fem
