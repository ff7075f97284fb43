// Finite element model of one flexible body: its solid part and arms assembled side by side
// ("full" dofs: solid, then every arm, then the 6 dofs of each interface point on the solid),
// joined by linear multipoint constraints, and condensed to the independent ("body") dofs.
//
// Constraints, all homogeneous and linear, x_full = T y_body:
//  - supports of the solid and the arms: the dof is zero;
//  - rigid tie (arm root to a solid region) and interface point on the solid: every region node
//    moves with the master's rigid motion, u_n = u_m + theta_m x (x_n - x_m);
//  - distributing tie: the arm root follows the region, u_r = mean(u_n) + theta x (x_r - x_c),
//    with theta the least-squares rotation of the region about its centroid x_c.
// Rigid motions satisfy every tie exactly, so a free body keeps its six zero-energy modes.
// The condensed matrices are T^T K T and T^T M T (Trilinos matrices with one sparsity pattern);
// the full mass, with point masses, stays available for inertia integrals.
//
// Distributed (a communicator of several processes: `mpirun -np N flextrack reduce`): every
// process holds the mesh, the nodes and T whole, but only its own rows of the matrices. The
// solid is partitioned by METIS (SolidModel); a process owns the condensed rows of the
// independent dofs of its part of the solid, the last process also those of the arms and the
// interface points (a body of arms only: equal blocks of rows, condensed by the last
// process). Each assembles its own cells and condenses its own rows of the parts; the few
// contributions that land in another process' rows (tie regions to their masters, an arm root
// to its region) are sent there. Vectors stay whole on every process: products with the
// matrices compute the own rows and gather them.
#pragma once

#include <fem/body.h>
#include <fem/curved_beam_model.h>
#include <fem/solid_model.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::fem
{
class BodyModel
{
public:
  /// Builds the parts' models and the constraints, distributed over @p communicator (a single
  /// process holds everything). Throws InputError for ties or interfaces that find no nodes, or
  /// interfaces that lie on a support. Collective over @p communicator.
  explicit BodyModel(const Body &body, MPI_Comm communicator = MPI_COMM_SELF);
  ~BodyModel();

  // --- the condensed (independent) dofs y --------------------------------------------------
  unsigned int n_dofs() const { return n_body_dofs; }
  const dealii::TrilinosWrappers::SparseMatrix &stiffness_matrix() const { return stiffness; }
  const dealii::TrilinosWrappers::SparseMatrix &mass_matrix() const { return mass; }
  /// True if any dof is fixed by a support (the body cannot move rigidly).
  bool is_supported() const { return supported; }
  /// dst = K src and dst = M src for whole body-dof vectors (on every process, collective when
  /// distributed).
  void stiffness_vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const;
  void mass_vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const;

  // --- distribution of the matrices' rows (one block of body dofs per process, in rank order) --
  bool distributed() const { return first_rows.size() > 2; }
  MPI_Comm communicator() const { return comm; }
  /// This process' rows of stiffness_matrix() and mass_matrix(): [first_owned_row(), + n_owned_rows()).
  unsigned int first_owned_row() const { return own_begin; }
  unsigned int n_owned_rows() const { return own_end - own_begin; }

  struct Interface
  {
    std::string name;
    dealii::Point<3> position;          ///< [m]
    std::array<unsigned int, 6> dofs{}; ///< body dofs of (u_x, u_y, u_z, theta_x, theta_y, theta_z)
  };
  const std::vector<Interface> &interfaces() const { return interface_list; }

  /// An output point: its full dofs (u, theta), which follow the body dofs through T (they are
  /// dependent, not in y). Values of a body-dof vector there: expand(y)[dofs[c]].
  struct OutputPoint
  {
    std::string name;
    dealii::Point<3> position;
    std::array<unsigned int, 6> full_dofs{};
  };
  const std::vector<OutputPoint> &output_points() const { return output_list; }

  /// The six rigid-body motions in body dofs: translations e_a (a = 0..2) and small rotations
  /// e_a x x about the origin (a = 3..5; arm and interface nodes also turn by e_a).
  std::array<dealii::Vector<double>, 6> rigid_body_modes() const;
  /// Body-dof load vector T^T f of a point force @p F [N] at arc length @p s [m] of arm @p arm.
  dealii::Vector<double> arm_point_load(unsigned int arm, double s, const dealii::Tensor<1, 3> &F) const;

  /// Displacement [m] at arc length @p s of arm @p arm for the body-dof vector @p y.
  dealii::Tensor<1, 3> arm_displacement(unsigned int arm, double s, const dealii::Vector<double> &y) const;

  // --- the full dofs x = T y (for integrals over the body and for drawing it) ---------------
  unsigned int n_full_dofs() const { return n_full; }
  dealii::Vector<double> expand(const dealii::Vector<double> &y) const;
  /// T^T f for a full-dof load vector.
  dealii::Vector<double> condense(const dealii::Vector<double> &f_full) const;
  /// dst = M_full src: the parts' consistent mass plus the point masses (whole vectors on every
  /// process; collective when distributed).
  void full_mass_vmult(dealii::Vector<double> &dst, const dealii::Vector<double> &src) const;
  /// Y = M_full X for @p m vectors stored column by column (n_full_dofs() each): one pass over
  /// each part's matrix for all of them (collective when distributed).
  void full_mass_multiply(const double *X, unsigned int m, double *Y) const;

  /// A node of the full model: its position and its full dofs (theta = -1 on solid nodes).
  struct Node
  {
    dealii::Point<3> x;
    std::array<int, 3> u{{-1, -1, -1}};
    std::array<int, 3> theta{{-1, -1, -1}};
  };
  const std::vector<Node> &full_nodes() const { return nodes; }
  /// Index in full_nodes() of the solid node that carries solid dof @p dof (any component).
  unsigned int node_of_solid(unsigned int dof) const { return node_of_solid_dof[dof]; }

  const SolidModel *solid_model() const { return solid.get(); }
  unsigned int n_arms() const { return arm_models.size(); }
  const CurvedBeamModel &arm_model(unsigned int a) const { return *arm_models[a]; }
  unsigned int arm_offset(unsigned int a) const { return arm_offsets[a]; }
  const std::string &arm_name(unsigned int a) const { return description.arm_names[a]; }
  /// The body this model was built from (its arms' sections, point masses, ...).
  const Body &body() const { return description; }

private:
  struct Entry
  {
    unsigned int column;
    double value;
  };
  /// Refuses (SolverError) a solid whose model will not fit in the memory left (base/memory.h).
  static void check_memory_for_solid(const Solid &solid, MPI_Comm communicator);
  void collect_nodes();
  // The constraints x = T y of supports, ties, interfaces and output points, in these steps:
  void build_constraints();
  /// First of the 6 dofs of each point on the solid (0 for points on arms); extends n_full.
  std::vector<unsigned int> number_reference_nodes(const std::vector<InterfacePoint> &points);
  void add_supports(dealii::AffineConstraints<double> &c) const;
  void add_ties(dealii::AffineConstraints<double> &c) const;
  void add_interfaces(dealii::AffineConstraints<double> &c, const std::vector<unsigned int> &first_dof);
  void add_output_points(dealii::AffineConstraints<double> &c, const std::vector<unsigned int> &first_dof);
  void add_point_masses();
  void build_transformation(const dealii::AffineConstraints<double> &c);
  /// The first body row of every process (and n_dofs() at the end), from the solid's partition.
  void distribute_rows();
  void condense_matrices();
  /// Y += point masses x X (full dofs, @p m columns).
  void add_point_masses_product(const double *X, unsigned int m, double *Y) const;
  /// dst = A src for the body matrix @p A (whole vectors): the own rows, gathered.
  void body_vmult(const dealii::TrilinosWrappers::SparseMatrix &A, dealii::Vector<double> &dst,
                  const dealii::Vector<double> &src) const;
  /// Whether this process computes the arms' rows and the point masses (the last one does).
  bool holds_arms() const { return first_rows.size() <= 2 || rank + 2 == first_rows.size(); }
  std::vector<unsigned int> region_nodes(const NodeRegion &region, const dealii::Point<3> &centre,
                                         const std::string &entry, const std::string &what) const;
  /// Throws unless the region's nodes span a plane (else they cannot carry a rotation).
  void check_spread(const std::vector<unsigned int> &region, const std::string &entry, const std::string &what) const;
  /// Full dofs (u, theta) of the arm node at arc length s.
  std::array<unsigned int, 6> arm_node_dofs(unsigned int arm, double s) const;

  const Body &description;
  MPI_Comm comm;
  unsigned int rank = 0;
  std::vector<unsigned int> first_rows{0, 0}; // first body row of each process, then n_body_dofs
  unsigned int own_begin = 0, own_end = 0;
  std::vector<std::unique_ptr<Arm>> arms;  // copies with a mesh node at every interface
  std::unique_ptr<SolidModel> solid;
  std::vector<std::unique_ptr<CurvedBeamModel>> arm_models;
  std::vector<unsigned int> arm_offsets;
  unsigned int n_full = 0, n_body_dofs = 0;
  bool supported = false;
  std::vector<Node> nodes;
  std::vector<int> node_of_solid_dof; // solid x-dof -> node index
  std::vector<Interface> interface_list;
  std::vector<OutputPoint> output_list;
  std::vector<std::array<unsigned int, 6>> interface_full_dofs;
  std::vector<std::pair<std::array<unsigned int, 2>, double>> point_mass_entries; // full (i, j), value
  // T, row by row: full dof i -> entries [t_start[i], t_start[i+1]) of t_entries
  std::vector<unsigned int> t_start;
  std::vector<Entry> t_entries;
  std::vector<unsigned int> full_of_column; // the full dof that each independent dof is
  dealii::TrilinosWrappers::SparseMatrix stiffness, mass;
};
} // namespace flextrack::fem
