// Craig-Bampton reduction of an arm (Craig & Bampton, AIAA J. 6(7), 1968): the displacement
// field is spanned by k fixed-interface normal modes (the interface clamped) and the static
// constraint modes of the interface (unit displacement of one interface dof, the others fixed,
// no load elsewhere). Interface loads are reproduced exactly by the constraint modes; the
// fixed-interface modes add the dynamics. The interface is the mesh node at arc length s
// (6 dofs).
#pragma once

#include <fem/arm.h>
#include <reduction/modal_solver.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace flextrack::reduction
{
struct ReducedModel
{
  std::vector<dealii::Vector<double>> basis;    ///< columns of Phi (full-model dof vectors)
  unsigned int n_normal_modes = 0;              ///< the first n_normal_modes columns
  std::vector<unsigned int> interface_dofs;     ///< full-model dofs of the interface node
  dealii::FullMatrix<double> stiffness, mass;   ///< Phi^T K Phi, Phi^T M Phi
  /// Frequencies [Hz] of the reduced model, ascending.
  std::vector<double> frequencies_hz() const;
  /// Static response to the full-model load vector f: Phi (Phi^T K Phi)^{-1} Phi^T f.
  dealii::Vector<double> static_response(const dealii::Vector<double> &f) const;
};

/// Craig-Bampton basis of @p arm (its supports as given) with the interface node at arc
/// length @p interface_s and @p n_normal_modes fixed-interface modes.
ReducedModel craig_bampton(const fem::Arm &arm, double interface_s, unsigned int n_normal_modes,
                           const ModalSettings &settings = ModalSettings());
/// A basis for an arm that carries a sliding contact: its @p n_normal_modes lowest modes and
/// the static responses to unit forces along x, y and z at @p n_stations stations
/// s_k = k L / n_stations (k = 1..n), mass-orthonormalised against the modes and each other
/// (Gram-Schmidt in the M inner product; dependent vectors are dropped), so that a concentrated
/// load at any arc length is represented (FORMULATION.md sec. 7).
ReducedModel track_load_basis(const fem::Arm &arm, unsigned int n_normal_modes, unsigned int n_stations,
                              const ModalSettings &settings = ModalSettings());
} // namespace flextrack::reduction
