// Measures of a solid's static solution on a node set (issue 12), next to the loads of
// fem/solid_loads.cc: the best-fit small rotation of the set's nodes.
#pragma once

#include <fem/solid_model.h>

#include <deal.II/base/tensor.h>
#include <deal.II/lac/vector.h>

#include <string>

namespace flextrack::fem
{
/// The small rotation theta [rad] of node set @p set that fits the nodal displacements @p u best
/// in the least-squares sense about the nodes' centroid c: minimises sum |u_i - u_c - theta x r_i|^2,
/// r_i = x_i - c, i.e. J theta = sum r_i x u_i with J = sum (|r_i|^2 1 - r_i r_i^T). For a
/// rigid motion of the set it is that motion's rotation exactly.
/// @p solid: the description @p model was built from (its node sets).
dealii::Tensor<1, 3> mean_rotation(const SolidModel &model, const Solid &solid, const std::string &set,
                                   const dealii::Vector<double> &u);
} // namespace flextrack::fem
