#include <reduction/reduced_body.h>

namespace flextrack::reduction
{
using namespace dealii;

FullMatrix<double> stiffness_with_inertial_loads(const ReducedBody &body, const Tensor<1, 3> &w, const Tensor<1, 3> &a,
                                                 const Tensor<1, 3> &alpha)
{
  FullMatrix<double> K = body.stiffness;
  if (body.geometric_stiffness.empty()) return K;
  const double c[12] = {w[0] * w[0], w[1] * w[1], w[2] * w[2], w[0] * w[1], w[0] * w[2], w[1] * w[2],
                        a[0],        a[1],        a[2],        alpha[0],    alpha[1],    alpha[2]};
  for (unsigned int k = 0; k < 12; ++k)
    if (c[k] != 0) K.add(c[k], body.geometric_stiffness[k]);
  return K;
}
} // namespace flextrack::reduction
