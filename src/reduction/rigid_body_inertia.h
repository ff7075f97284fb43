// Rigid-body inertia of a body's finite element model, from its consistent mass matrix: with R
// the six rigid-body motions (translations e_i; rotations e_i x x, which for beams also turn
// the section rotations by e_i), R^T M R = [[m 1, m [e_j x c]_i], [..., J_O]], from which the
// mass m, the centre of mass c and the inertia tensor follow. It is the body as a free solid:
// supports are removed. Exact for solids (rigid motions are linear, in every element's space)
// and for straight arms; for curved arms exact up to the interpolation of e_i x x(s).
#pragma once

#include <fem/arm.h>
#include <fem/solid.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

namespace flextrack::reduction
{
struct RigidBodyInertia
{
  double mass = 0;                           ///< [kg]
  dealii::Point<3> centre_of_mass;           ///< [m]
  dealii::Tensor<2, 3> inertia_about_centre; ///< [kg m^2], about the centre of mass, global axes
};

RigidBodyInertia rigid_body_inertia(const fem::Solid &solid);
RigidBodyInertia rigid_body_inertia(const fem::Arm &arm);
} // namespace flextrack::reduction
