// Modal participation factors and effective modal masses (as CalculiX prints them), in the three
// translation directions of the supports' rigid motion.
//
// With mass-normalised modes phi_k (phi_k^T M phi_k = 1) and the rigid translation r_d (1 in
// every displacement dof of direction d, 0 in rotation dofs), the participation factor is
// Gamma_kd = phi_k^T M r_d and the effective mass m_kd = Gamma_kd^2 [kg]. Summed over all modes,
// m_kd gives r_d^T M r_d, the mass that moves with the supports' translation: the mass of the
// free part (supported dofs have zero rows in M).
#pragma once

#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <vector>

namespace flextrack::reduction
{
struct ModalParticipation
{
  std::vector<std::array<double, 3>> factors;        ///< Gamma_kd [sqrt(kg)], per mode
  std::vector<std::array<double, 3>> effective_mass; ///< Gamma_kd^2 [kg], per mode
  std::array<double, 3> total_mass{};                ///< r_d^T M r_d [kg]
};

/// @p component: the displacement direction (0, 1, 2) of every dof, or 3 and above for
/// rotations (not a translation).
ModalParticipation modal_participation(const std::vector<dealii::Vector<double>> &shapes,
                                       const dealii::TrilinosWrappers::SparseMatrix &M,
                                       const std::vector<unsigned int> &component);
} // namespace flextrack::reduction
