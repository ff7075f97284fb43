// Modal participation factors and effective modal masses (as CalculiX prints them), in the three
// translation directions and the three rotations of the supports' rigid motion, and a short
// classification of every mode.
//
// With mass-normalised modes phi_k (phi_k^T M phi_k = 1) and a rigid motion r_d, the
// participation factor is Gamma_kd = phi_k^T M r_d and the effective mass m_kd = Gamma_kd^2.
// Translation d (x, y, z): r_d is 1 in every displacement dof of direction d, 0 elsewhere;
// m_kd in kg. Rotation about the axis e_d through the reference point x_ref (rx, ry, rz): a
// displacement dof at node position x gets the component of e_d x (x - x_ref), a rotation dof
// of an arm the component of e_d; m_kd in kg m^2. Summed over all modes, m_kd gives
// r_d^T M r_d: the mass (or the moment of inertia about the axis) of what moves with the
// supports' rigid motion, i.e. of the free part (supported dofs have zero rows in M).
//
// Classification. An arm's mode is split by kinetic energy in the section frame (t, y, z) of
// every node: phi = phi_axial + phi_in + phi_out + phi_torsion, where at each node
//   axial        = (u . t) t                      (displacement along the tangent),
//   in-plane     = (u . y) y + (theta . z) z      (bending: deflection along the section y axis),
//   out-of-plane = (u . z) z + (theta . y) y      (bending: deflection along the section z axis),
//   torsion      = (theta . t) t                  (rotation about the tangent),
// and e_c = phi_c^T M phi_c with the consistent mass. The shares e_c / sum e_c are exact for a
// straight arm (the four parts are M-orthogonal there); on a curved arm the cross terms, of the
// order of the frame's turn across an element, are left out. The kind is the largest share.
// A solid's mode is labelled by the direction (x, y, z, rx, ry, rz) of its largest effective
// mass fraction.
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/base/types.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace flextrack::fem
{
class CurvedBeamModel;
class SolidModel;
} // namespace flextrack::fem

namespace flextrack::reduction
{
/// Directions of the rigid motions: translations x, y, z, then rotations rx, ry, rz.
inline constexpr std::array<const char *, 6> rigid_direction_names = {{"x", "y", "z", "rx", "ry", "rz"}};

/// What every dof of a model is and where it sits.
struct DofLayout
{
  /// 0, 1, 2: displacement x, y, z; 3, 4, 5: rotation about x, y, z (arms only).
  std::vector<unsigned int> component;
  std::vector<dealii::Point<3>> position; ///< the dof's node [m]

  /// An arm's node: its six dofs (u then theta) and its section frame.
  struct SectionNode
  {
    std::array<dealii::types::global_dof_index, 6> dofs;
    dealii::Tensor<1, 3> t, y, z;
  };
  std::vector<SectionNode> section_nodes; ///< arms only; empty for solids
};

/// Nodes at the exact centre line: a dof of cell [s0, s1] with unit support point xi sits at
/// arc length s0 + xi (s1 - s0), where the model's own integrands place it.
DofLayout dof_layout(const fem::CurvedBeamModel &arm);
/// Nodes at the support points of the element, mapped by the body's 20-node geometry (the
/// serendipity element has unit support points: its 20 nodes).
DofLayout dof_layout(const fem::SolidModel &solid);

/// The six rigid motions r_d of the layout, rotations about axes through @p x_ref.
std::array<dealii::Vector<double>, 6> rigid_motions(const DofLayout &layout, const dealii::Point<3> &x_ref);

struct ModalParticipation
{
  /// Gamma_kd per mode: [sqrt(kg)] for x, y, z; [sqrt(kg) m] for rx, ry, rz.
  std::vector<std::array<double, 6>> factors;
  /// Gamma_kd^2 per mode: [kg] for x, y, z; [kg m^2] for rx, ry, rz.
  std::vector<std::array<double, 6>> effective_mass;
  /// r_d^T M r_d: moving mass [kg] (x, y, z), moment of inertia about the axes [kg m^2] (rx, ry, rz).
  std::array<double, 6> total_mass{};
  dealii::Point<3> reference_point; ///< x_ref of the rotations [m]

  /// effective_mass[k][d] / total_mass[d], 0 where nothing moves in direction d.
  double fraction(std::size_t k, unsigned int d) const
  {
    return total_mass[d] > 0 ? effective_mass[k][d] / total_mass[d] : 0.0;
  }
  /// The direction (0..5) of mode k's largest fraction; 6 if every fraction is below 1e-3.
  unsigned int dominant_direction(std::size_t k) const;
};

/// y = M x with the model's consistent mass: an assembled matrix, or a solid's cell-by-cell
/// product (fem::SolidMassOperator) once its matrices are released.
using MassProduct = std::function<void(const dealii::Vector<double> &x, dealii::Vector<double> &y)>;
/// The product of an assembled M.
MassProduct product_with(const dealii::TrilinosWrappers::SparseMatrix &M);

ModalParticipation modal_participation(const std::vector<dealii::Vector<double>> &shapes, const MassProduct &M,
                                       const DofLayout &layout, const dealii::Point<3> &x_ref = dealii::Point<3>());
inline ModalParticipation modal_participation(const std::vector<dealii::Vector<double>> &shapes,
                                              const dealii::TrilinosWrappers::SparseMatrix &M, const DofLayout &layout,
                                              const dealii::Point<3> &x_ref = dealii::Point<3>())
{
  return modal_participation(shapes, product_with(M), layout, x_ref);
}

/// A mode's kind: for an arm the largest kinetic-energy share ("axial", "bending in-plane",
/// "bending out-of-plane", "torsion"), for a solid the dominant direction ("x" .. "rz", or "-").
struct ModeClass
{
  std::string kind;
  /// Arms: the kind's share of the kinetic energy, and all four (axial, in-plane,
  /// out-of-plane, torsion). Solids: the dominant direction's effective mass fraction.
  double share = 0;
  std::array<double, 4> energy_shares{};
};

inline constexpr std::array<const char *, 4> arm_mode_kinds = {
  {"axial", "bending in-plane", "bending out-of-plane", "torsion"}};

/// The class of every mode: by energy split where the layout has section nodes (arms), by
/// effective mass otherwise (solids).
std::vector<ModeClass> classify_modes(const std::vector<dealii::Vector<double>> &shapes, const MassProduct &M,
                                      const DofLayout &layout, const ModalParticipation &participation);
inline std::vector<ModeClass> classify_modes(const std::vector<dealii::Vector<double>> &shapes,
                                             const dealii::TrilinosWrappers::SparseMatrix &M, const DofLayout &layout,
                                             const ModalParticipation &participation)
{
  return classify_modes(shapes, product_with(M), layout, participation);
}
} // namespace flextrack::reduction
