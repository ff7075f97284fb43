// Finite element model of a curved, shear-deformable arm (linear Reissner / Timoshenko beam).
//
// Unknowns at every node, in global axes: displacement u (3) and small section rotation
// theta (3). With the exact tangent t(s) of the centre line and its arc length s,
//     Gamma = u' + t x theta     (axial strain and two shear strains)
//     kappa = theta'             (twist and two bending curvatures),
// taken in the section frame (t, y, z) where the constitutive law is diagonal:
//     D = diag(EA, k_y GA, k_z GA, GJ, E Iy, E Iz).
// The geometry is exact: every cell spans [s0, s1] of the true curve and the integrands use
// the curve's tangent and section frame at each quadrature point (an isoparametric centre
// line would cap the convergence of cubic elements at about h^5). Rigid motions are therefore
// represented up to the interpolation error: a free arm has six near-zero frequencies.
// The stiffness uses uniformly reduced Gauss integration (p points for degree p), which removes
// shear and membrane locking without spurious modes; the consistent mass, with rotary inertia
// rho diag(Ip, Iy, Iz), uses p + 1 points.
#pragma once

#include <fem/arm.h>
#include <fem/arm_mesh.h>
#include <fem/load_case.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <vector>

namespace flextrack::fem
{
/// Section forces at arc length s [m], in the section frame (t, y, z): the axial force N, the
/// shear forces Q_y, Q_z [N], the torque T and the bending moments M_y, M_z [N m]; the forces
/// the part beyond s exerts on the part before it (N > 0 in tension).
struct SectionForces
{
  double s = 0;
  std::array<double, 6> values{}; ///< N, Q_y, Q_z, T, M_y, M_z
};

class CurvedBeamModel
{
public:
  /// Mesh of arm.n_elements * 2^refinement cells; assembles K and M. With
  /// @p constrain_matrices false the supports are only listed in constraints(), and K and M are
  /// those of the free arm (a flexible body applies them with its ties, fem/body_model.h).
  CurvedBeamModel(const Arm &arm, unsigned int refinement = 0, bool constrain_matrices = true);

  const dealii::DoFHandler<1, 3> &dof_handler() const { return dofs; }
  const dealii::Mapping<1, 3> &mapping() const { return *map; }
  const dealii::TrilinosWrappers::SparseMatrix &stiffness_matrix() const { return stiffness; }
  /// The mapping (degree max(p, 3), on the curve manifold) is used to draw the curved cells.
  /// Consistent mass; rows of supported (constrained) dofs are zero.
  const dealii::TrilinosWrappers::SparseMatrix &mass_matrix() const { return mass; }
  const dealii::AffineConstraints<double> &constraints() const { return supports; }
  unsigned int n_dofs() const { return dofs.n_dofs(); }
  unsigned int n_free_dofs() const { return dofs.n_dofs() - supports.n_constraints(); }
  unsigned int n_cells() const { return mesh.n_cells(); }
  const Arm &arm() const { return description; }
  const ArmMesh &mesh_of_arm() const { return mesh; }
  /// Nodal load vector of a point force @p F [N] (global axes) at arc length @p s [m].
  dealii::Vector<double> point_load(double s, const dealii::Tensor<1, 3> &F) const;
  /// Geometric stiffness of the axial force in the deformed state @p u (a static solution):
  /// K_G = int N(s) u'_perp . v'_perp ds, N = EA t . u' the axial force [N], u'_perp the part of
  /// the displacement slope across the tangent. Same pattern as K; supports not applied.
  void geometric_stiffness(const dealii::Vector<double> &u, dealii::TrilinosWrappers::SparseMatrix &K_G) const;
  /// Displacement [m] at arc length @p s of the dof vector @p u.
  dealii::Tensor<1, 3> displacement_at(double s, const dealii::Vector<double> &u) const;
  /// Section rotation [rad] at arc length @p s of the dof vector @p u.
  dealii::Tensor<1, 3> rotation_at(double s, const dealii::Vector<double> &u) const;

  /// Adds the consistent nodal loads of a force @p F [N] and a moment @p M [N m] (global axes) at
  /// arc length @p s to @p f (supported dofs included: their share goes straight to the support).
  void add_point_load(double s, const dealii::Tensor<1, 3> &F, const dealii::Tensor<1, 3> &M,
                      dealii::Vector<double> &f) const;
  /// Adds the consistent nodal loads of a uniform force per length @p q [N/m] on s0 <= s <= s1.
  void add_line_load(double s0, double s1, const dealii::Tensor<1, 3> &q, dealii::Vector<double> &f) const;
  /// The nodal load vector of a load case (point and line loads, gravity on rho A).
  dealii::Vector<double> load_vector(const LoadCase &load_case) const;
  /// The prescribed values of a load case's support displacements at their dofs (u, and theta
  /// where given), zero elsewhere: the inhomogeneous supports of a static solve.
  dealii::Vector<double> support_displacements(const LoadCase &load_case) const;
  /// Section forces D (Gamma, kappa) of the solution @p u along the arm, in the order of s: per
  /// cell at its start, its p Gauss points and its end (a jump at a point load shows as two
  /// samples at the same s).
  std::vector<SectionForces> section_forces(const dealii::Vector<double> &u) const;
  /// The section forces as a field on dof_handler() (components N, Q_y, Q_z, T, M_y, M_z in
  /// the places of u and theta): each cell's values at its nodes, averaged where cells meet.
  dealii::Vector<double> section_force_field(const dealii::Vector<double> &u) const;
  /// Resultant about the origin of nodal forces @p r at the mesh vertices (reactions: the
  /// supports are vertices): sum of the forces, sum of x_k x F_k plus the nodal moments.
  Resultant vertex_resultant(const dealii::Vector<double> &r) const;

private:
  /// D = diag(EA, k_y GA, k_z GA, GJ, E I_y, E I_z).
  std::array<double, 6> section_stiffness() const;
  /// Section forces at reference coordinate @p xi of @p cell.
  SectionForces section_forces_in(const dealii::DoFHandler<1, 3>::active_cell_iterator &cell, double xi,
                                  const dealii::Vector<double> &u) const;
  /// The cell holding arc length s, and s's reference coordinate in it.
  std::pair<dealii::DoFHandler<1, 3>::active_cell_iterator, double> locate(double s) const;
  /// Components c0, c0 + 1, c0 + 2 of the field @p u at arc length @p s.
  dealii::Tensor<1, 3> field_at(double s, const dealii::Vector<double> &u, unsigned int c0) const;
  void setup_dofs();
  void apply_supports();
  void assemble();

  const Arm &description;
  bool constrained_assembly;
  ArmMesh mesh;
  dealii::FESystem<1, 3> fe;
  std::unique_ptr<dealii::MappingQ<1, 3>> map;
  dealii::DoFHandler<1, 3> dofs;
  dealii::AffineConstraints<double> supports;
  dealii::TrilinosWrappers::SparseMatrix stiffness, mass;
};
} // namespace flextrack::fem
