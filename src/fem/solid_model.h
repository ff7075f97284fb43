// Finite element model of a linear elastic 3D body: stiffness and consistent mass assembled
// into Trilinos matrices, on the 20-node isoparametric geometry of its mesh.
//
// Geometry: every cell is mapped by the 20-node serendipity map of its coarse ancestor
// (MappingFEField over FESystem(FE_Serendipity, 3)), so curved edges read from a file are kept
// exactly on every refinement level. Unknowns: the displacement (3 components) with the chosen
// element (hex20, hex8 or hex27). K = int eps(v) : C eps(u) for an isotropic C, M = int rho v.u,
// both with the chosen Gauss rule (full 3x3x3 for hex20, as CalculiX's C3D20).
//
// Under MPI the mesh is a parallel::shared::Triangulation partitioned by METIS: every process
// keeps the whole mesh (and geometry), assembles its own cells, and owns a block of rows of the
// distributed Trilinos matrices.
#pragma once

#include <base/mpi_session.h>
#include <fem/load_case.h>
#include <fem/solid.h>
#include <fem/solid_mass_operator.h>

#include <deal.II/distributed/shared_tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/fe/mapping_fe_field.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <vector>

namespace flextrack::fem
{
class SolidModel
{
public:
  /// The body's mesh refined @p refinement times (each cell split into 8). With
  /// @p constrain_matrices false the supports are only listed in constraints(), and K and M are
  /// those of the free body (a flexible body applies them with its ties, fem/body_model.h).
  /// With @p with_mass false, M is not assembled (mass_matrix() is empty): linear statics need K
  /// only, and M would be a third of the memory before the factorisation. The mesh is shared
  /// over @p communicator: MPI_COMM_SELF keeps the whole model on this process (a flexible body,
  /// which every process of a distributed reduction builds whole, fem/body_model.h).
  SolidModel(const Solid &solid, unsigned int refinement = 0, bool constrain_matrices = true, bool with_mass = true,
             MPI_Comm communicator = base::fe_communicator());

  const dealii::DoFHandler<3> &dof_handler() const { return dofs; }
  const dealii::Mapping<3> &mapping() const { return *map; }
  const dealii::TrilinosWrappers::SparseMatrix &stiffness_matrix() const { return stiffness; }
  /// Consistent mass; rows of supported dofs are zero (if the matrices are constrained).
  const dealii::TrilinosWrappers::SparseMatrix &mass_matrix() const { return mass; }
  /// The consistent mass applied cell by cell (fem/solid_mass_operator.h): the product of
  /// mass_matrix() in a small fraction of its memory, also after release_matrices(). Built on
  /// first use.
  const SolidMassOperator &mass_operator() const;
  /// Frees K and M: stiffness_matrix() and mass_matrix() are empty afterwards. The eigen solve
  /// of a large solid calls it once the factorisation has its own copy of K - sigma M.
  void release_matrices();
  /// Frees K only (stiffness_matrix() is empty afterwards); M keeps the graph they share.
  void release_stiffness();
  const dealii::AffineConstraints<double> &constraints() const { return supports; }
  unsigned int n_dofs() const { return dofs.n_dofs(); }
  unsigned int n_free_dofs() const { return dofs.n_dofs() - supports.n_constraints(); }
  unsigned int n_cells() const { return tria.n_active_cells(); }
  /// Dof indices (x, y, z) at a node of the coarse mesh (refinement 0 only); empty if the
  /// element has no dof there (hex8 at a mid-side node).
  std::vector<dealii::types::global_dof_index> node_dofs(const MeshNode &node) const;
  /// Positions of all dofs' support points (for planes, loads and checks).
  std::vector<dealii::Point<3>> support_points() const;

  /// Static loads (fem/solid_loads.cc, refinement 0): the nodal load vector of a load case's node
  /// set forces and gravity (rho g per volume); arm loads are not for solids.
  dealii::Vector<double> load_vector(const LoadCase &load_case) const;
  /// The prescribed values of a load case's support displacements at the dofs their supports fix
  /// (refinement 0), zero elsewhere: the inhomogeneous supports of a static solve.
  dealii::Vector<double> support_displacements(const LoadCase &load_case) const;
  /// The six rigid motions (translations along x, y, z; small rotations about the x, y, z axes
  /// through the origin) as dof vectors: the near-null space of the free body's K.
  std::vector<dealii::Vector<double>> rigid_body_modes() const;
  /// The internal forces K u, summed cell by cell as K_e (u_e - R_e a_e) with each cell's
  /// best-fit rigid motion R_e a_e taken out first (in long double). Mathematically K u; in
  /// floating point their resultant is free of the round-off of K on rigid motions (K R = 0 only
  /// to eps |K|, times the large rigid part of a bending solution), so reactions computed from
  /// them balance the loads to round-off of the deformation itself. Costs one assembly.
  std::vector<long double> internal_forces(const std::vector<long double> &u) const;
  /// Resultant about the origin of the nodal forces @p r (at the dofs' support points).
  Resultant nodal_resultant(const dealii::Vector<double> &r) const;
  /// Mean displacement [m] of the nodes of node set @p set in the solution @p u.
  dealii::Tensor<1, 3> mean_displacement(const std::string &set, const dealii::Vector<double> &u) const;

private:
  /// The displacement component (0, 1, 2) of every dof.
  std::vector<unsigned int> dof_components() const;
  /// The dofs that @p support fixes: on its plane (any refinement), or at its node set's nodes
  /// (refinement 0). @p points, @p component: support_points() and dof_components() (needed for
  /// a plane only).
  std::vector<dealii::types::global_dof_index> support_dofs(const SolidSupport &support,
                                                            const std::vector<dealii::Point<3>> &points,
                                                            const std::vector<unsigned int> &component) const;
  /// Stiffness (and mass, if @p m_cell) matrix of @p cell, lower triangles (j <= i) only.
  void cell_matrices(dealii::FEValues<3> &values, const dealii::DoFHandler<3>::active_cell_iterator &cell,
                     dealii::FullMatrix<double> &k_cell, dealii::FullMatrix<double> *m_cell) const;
  void setup_geometry();
  void tabulate_node_dofs();
  void apply_supports();
  /// A supported solid whose mesh falls into parts that share no node must support every part:
  /// an unsupported part floats freely (InputError naming Solid/Supports).
  void refuse_unsupported_parts() const;
  void assemble();

  const Solid &body;
  unsigned int level;
  bool constrained_assembly;
  bool assemble_mass;
  dealii::parallel::shared::Triangulation<3> tria;
  dealii::FESystem<3> geometry_fe;
  dealii::DoFHandler<3> geometry_dofs;
  dealii::Vector<double> positions;
  std::unique_ptr<dealii::MappingFEField<3, 3, dealii::Vector<double>>> map;
  std::unique_ptr<dealii::FESystem<3>> fe;
  dealii::DoFHandler<3> dofs;
  dealii::AffineConstraints<double> supports;
  std::map<MeshNode, std::vector<dealii::types::global_dof_index>> dofs_at_node;
  dealii::TrilinosWrappers::SparseMatrix stiffness, mass;
  mutable std::unique_ptr<SolidMassOperator> cell_mass;
};
} // namespace flextrack::fem
