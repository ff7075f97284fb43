// The multibody system as one DAE: the stabilised index-2 form of Gear, Gupta and Leimkuhler.
//
// Unknowns y = (q, v, lambda, mu): positions q (per body R, p, eta; then the joints' own
// coordinates), velocities v (per body R', omega, eta'; then the joints' own), multipliers lambda
// of the velocity constraints and mu of the position constraints. The residual, in that order
// of rows (so that row i and unknown i share a name):
//   F_q      = q' - T(q) v + Phi_q^T mu           (n_q)
//   F_v      = M(q) v' - Q(q, v, t) + B^T lambda  (n_v)
//   F_lambda = B v + Phi_t                        (joint equations)
//   F_mu     = Phi(q, t)                          (joint equations, then |p|^2 - 1 per body)
// The Euler-parameter normalisation is a position constraint only: its velocity form 2 p^T p'
// = p^T G^T omega vanishes identically (G p = 0), so a velocity row would make the Jacobian
// singular. Redundant joint equations found at the start (dependent there and nearby:
// multibody/redundancy.h) are dropped from both sets, and watched during the run.
//
// The Jacobian dF/dy + alpha dF/dy' is assembled element by element (bodies, joints, forces)
// into an Epetra_CrsMatrix on an Epetra_SerialComm (no MPI needed) whose pattern is fixed once:
// the bodies', joints' and forces' blocks are analytic (a track contact's marker contributes
// central differences of itself alone; system_jacobian.cc); an element without analytic
// derivatives (two markers on one body) takes central differences of its own residual
// (element-local, so a column costs one element evaluation, not a system one). It is factorised
// by KLU or LAPACK's dense LU (jacobian_solver.h).
#pragma once

#include <multibody/body.h>
#include <multibody/force.h>
#include <multibody/joint.h>
#include <multibody/joint_table.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <memory>
#include <string>
#include <vector>

class Epetra_CrsMatrix;

namespace flextrack::multibody
{
class JacobianSolver;

/// A joint equation that was found dependent on others and dropped.
struct DroppedEquation
{
  std::string joint;
  unsigned int equation;
  std::string description;
};

class System
{
public:
  /// @p gravity [m/s^2], global.
  explicit System(const Vector3 &gravity = Vector3());
  ~System();

  // Building
  const Body &ground() const { return *bodies[0].body; }
  const Body &add_body(std::unique_ptr<Body> body);
  void add_joint(std::unique_ptr<Joint> joint);
  void add_force(std::unique_ptr<Force> force);
  const Body *find_body(const std::string &name) const;
  BodyLookup body_lookup() const;
  const Vector3 &gravity() const { return g; }

  /// Lays out the coordinates; all joint equations active. Call once after building.
  void finalize();
  /// Drops joint equations (pairs joint index, equation); re-lays out the multipliers.
  void drop_equations(const std::vector<std::pair<unsigned int, unsigned int>> &equations);
  const std::vector<DroppedEquation> &dropped_equations() const { return dropped; }

  // Watching the dropped equations (multibody/redundancy.h). They were dropped because they
  // depend on the others at and near the start; they hold as long as that stays so.
  /// A dropped equation may be off by this times its scale s_r (1e-6 of the scene's length for a
  /// translation, 1e-6 rad for a rotation), plus 100 times the active equations' scaled residual
  /// (a dependent equation is a combination of the active ones: it inherits their residual).
  static constexpr double dropped_equation_tolerance = 1e-6;
  /// Scales s_r of the joint equations (rows of constraint_rows(true)) [m or -]: Phi_r / s_r is
  /// dimensionless. 1 until set.
  void set_equation_scales(std::vector<double> scales) { equation_scale = std::move(scales); }
  /// max |Phi_r| / s_r over the active equations (@p of_dropped false) or the dropped ones;
  /// @p worst (optional): that row, of constraint_rows(true).
  double scaled_residual(double t, const dealii::Vector<double> &y, bool of_dropped, unsigned int *worst = nullptr) const;
  /// Positive while the dropped equations hold (a root function of the run): the allowed
  /// scaled residual minus theirs.
  double dropped_equation_margin(double t, const dealii::Vector<double> &y) const;
  /// The sentence on the dropped equation that holds worst at (t, y), and what to change.
  std::string dropped_equation_report(double t, const dealii::Vector<double> &y) const;

  // Layout
  unsigned int n_q() const { return nq; }
  unsigned int n_v() const { return nv; }
  unsigned int n_lambda() const { return nlambda; }
  unsigned int n_mu() const { return nmu; }
  unsigned int size() const { return nq + nv + nlambda + nmu; }
  unsigned int n_bodies() const { return bodies.size(); } ///< including the ground (index 0)
  const Body &body(unsigned int b) const { return *bodies[b].body; }
  unsigned int q_offset(unsigned int b) const { return bodies[b].q; }
  unsigned int v_offset(unsigned int b) const { return bodies[b].v; }
  unsigned int n_joints() const { return joints.size(); }
  const Joint &joint(unsigned int j) const { return *joints[j].joint; }
  unsigned int n_forces() const { return forces.size(); }
  /// Offset of joint @p j's multipliers in lambda (and in mu) and its active equations.
  unsigned int multiplier_offset(unsigned int j) const { return joints[j].multiplier; }
  const std::vector<unsigned int> &active_equations(unsigned int j) const { return joints[j].active; }
  /// "body crank, omega_z", "joint pin, position constraint: rotation about x ...".
  std::string component_name(unsigned int i) const;

  /// q and v from the bodies' and joints' initial states; lambda = mu = 0.
  void initial_guess(dealii::Vector<double> &y) const;
  /// 1 for differential components (q, and v with mass), 0 for algebraic ones.
  void differential_components(dealii::Vector<double> &id) const;

  // The DAE
  void residual(double t, const dealii::Vector<double> &y, const dealii::Vector<double> &yp,
                dealii::Vector<double> &F) const;
  /// dF/dy + alpha dF/dy' into jacobian(); counts evaluations.
  void assemble_jacobian(double t, double alpha, const dealii::Vector<double> &y, const dealii::Vector<double> &yp);
  /// dF/dy into jacobian() and dF/dy' into @p dF_dyp (dense, column major, size() x size()) in one
  /// pass: the Jacobian at alpha = 0 and the terms alpha multiplies, which only the kinematic rows
  /// (q'), the bodies' equations of motion (M(q) v', geometric stiffening) and the joints' own q'
  /// hold. Radau IIA needs both; two assemblies at alpha = 0 and 1 evaluated every joint and
  /// force twice. Counts one evaluation.
  void assemble_jacobian_parts(double t, const dealii::Vector<double> &y, const dealii::Vector<double> &yp,
                               std::vector<double> &dF_dyp);
  const Epetra_CrsMatrix &jacobian() const;
  /// The Jacobian's sparsity pattern, row by row: every element's rows x (its columns, its
  /// multipliers), and the diagonal; each row's columns sorted, without repeats.
  std::vector<std::vector<int>> jacobian_pattern() const;
  /// LU factorisation of jacobian() (KLU or dense, jacobian_solver.h); false if it is singular.
  /// @p fresh_pivots: search pivots afresh (KLU), not reuse the last order (jacobian_solver.h).
  bool factorize(bool fresh_pivots = false);
  /// x = J^{-1} b (after factorize()); x and b may alias.
  void solve(const double *b, double *x);
  unsigned long n_jacobian_evaluations() const { return jacobian_count; }
  /// Factorisations that condensed the positions out (condensed_lu.h), and the unknowns left in
  /// their LU; 0 before the first factorisation or on KLU.
  unsigned long n_condensed_factorizations() const;
  unsigned int condensed_size() const;
  /// Take every joint's and force's derivatives by central differences of its residual, also
  /// where it has analytic ones (Joint::derivatives, Force::derivatives): the test oracle.
  void use_element_differences(bool differences) { element_differences_only = differences; }
  /// Assemble the Newton matrix of a time step, not the exact Jacobian: without the joints'
  /// d(Phi_q^T mu)/dq. The stabilisation multipliers mu vanish on the exact solution and stay of
  /// the order of the local error / h in a step, so the term is negligible beside cj I in the same
  /// rows; without it the position rows' block cj I - d(T v)/dq splits by body frame and
  /// coordinate, and the dense LU condenses the positions out (condensed_lu.h: the laser robot's
  /// LU of 170 unknowns becomes one of 104). Set by the time integrators; the exact Jacobian
  /// (default) is for linearisation, static stiffness and the tests.
  void use_newton_matrix(bool newton) { newton_matrix = newton; }

  // Pieces for initial conditions, monitors, linearisation (all in v-coordinates, dense)
  void mass_matrix(const dealii::Vector<double> &y, dealii::FullMatrix<double> &M) const;
  /// Q at (t, y); @p v_dot (n_v, optional): the accelerations, for forces that depend on them.
  void generalized_forces(double t, const dealii::Vector<double> &y, dealii::Vector<double> &Q,
                          const dealii::Vector<double> *v_dot = nullptr) const;
  /// Joint equations (all, or the active ones) at y: Phi, B (rows x n_v) and Phi_t.
  void constraints(double t, const dealii::Vector<double> &y, bool all_equations, dealii::Vector<double> &phi,
                   dealii::FullMatrix<double> &B, dealii::Vector<double> &phi_t) const;
  /// The largest |Phi| and |B v + Phi_t| over every joint equation (the dropped ones included),
  /// as from constraints(.., true, ..) without forming B; NaN where a row is NaN.
  void constraint_residuals(double t, const dealii::Vector<double> &y, double &position, double &velocity) const;
  /// (joint, equation) of each row of constraints(.., all_equations, ..).
  std::vector<std::pair<unsigned int, unsigned int>> constraint_rows(bool all_equations) const;
  /// q += T(q) dx for a displacement dx in v-coordinates; Euler parameters renormalised.
  void move_positions(dealii::Vector<double> &y, const dealii::Vector<double> &dx) const;
  /// q' = T(q) v.
  void coordinate_rates(const dealii::Vector<double> &y, dealii::Vector<double> &q_dot) const;

  // Limits of joints (the ends of tracks): functions positive while every joint is valid
  unsigned int n_limits() const;
  void limit_values(const dealii::Vector<double> &y, double *g) const;
  /// The sentence on limit @p i (of n_limits()) reached at @p y.
  std::string limit_report(unsigned int i, const dealii::Vector<double> &y) const;
  /// As above, with held end stops: a held stop's function is its push (Joint::EndStop), which
  /// turns negative where the stop would have to pull.
  void limit_values(double t, const dealii::Vector<double> &y, double *g) const;
  /// Limit @p i's behaviour, and the index in y of the velocity of the coordinate it bounds.
  Joint::EndStop end_stop(unsigned int i, unsigned int &velocity_index) const;
  /// Holds the coordinate of limit @p i at its stop (its velocity row reads v = 0 instead of the
  /// force balance along the track) or releases it.
  void set_held(unsigned int i, bool held);
  bool is_held(unsigned int i) const { return i < held_limit.size() && held_limit[i]; }
  /// True if velocity coordinate @p k (index in v) is held at a stop.
  bool velocity_held(unsigned int k) const { return k < held_velocity.size() && held_velocity[k]; }
  /// Energy that impacts at end stops have taken so far [J] (the monitors count it as dissipated).
  double impact_losses() const { return impact_energy; }
  void add_impact_loss(double joules) { impact_energy += joules; }
  /// Kinetic energy of all bodies at y [J].
  double kinetic_energy(const dealii::Vector<double> &y) const;
  /// Of the joints' own forces at (t, y): power of the applied part, dissipated power (>= 0) [W].
  void own_force_powers(double t, const dealii::Vector<double> &y, double &applied, double &dissipated) const;

  // Pointers to one body's or joint's coordinates in y
  const double *q_of(unsigned int b, const dealii::Vector<double> &y) const { return bodies[b].body->n_q() ? y.begin() + bodies[b].q : nullptr; }
  const double *v_of(unsigned int b, const dealii::Vector<double> &y) const { return bodies[b].body->n_v() ? y.begin() + nq + bodies[b].v : nullptr; }
  std::vector<const double *> joint_q(unsigned int j, const dealii::Vector<double> &y) const;
  /// Joint @p j's own coordinates in y (a track contact's arc length s; a sleeve's s_II, s_I), as
  /// Joint::evaluate() and Joint::reaction() take them; nullptr if it has none.
  const double *own_q_of(unsigned int j, const dealii::Vector<double> &y) const
  {
    return joints[j].joint->n_own_coordinates() ? y.begin() + joints[j].own_q : nullptr;
  }
  std::vector<const double *> force_q(unsigned int f, const dealii::Vector<double> &y) const;
  std::vector<const double *> force_v(unsigned int f, const dealii::Vector<double> &y) const;
  const Force &force(unsigned int f) const { return *forces[f].force; }

private:
  struct BodySlot
  {
    std::unique_ptr<Body> body;
    unsigned int q = 0, v = 0, normalisation = 0; // offsets; normalisation row in mu
  };
  struct JointSlot
  {
    std::unique_ptr<Joint> joint;
    std::vector<unsigned int> body_index;
    unsigned int own_q = 0, own_v = 0; // offsets of its own coordinates in q and v
    std::vector<unsigned int> active;  // active equations
    unsigned int multiplier = 0;       // offset in lambda and mu
  };
  struct ForceSlot
  {
    std::unique_ptr<Force> force;
    std::vector<unsigned int> body_index;
  };
  /// Rows an element writes and the state columns (q, v entries) it depends on.
  struct ElementIndices
  {
    std::vector<unsigned int> rows, columns;
  };

  void layout_multipliers();
  /// Joint @p j's own forces at (t, y), applied and dissipative parts (n_own_coordinates() each).
  void own_forces(unsigned int j, double t, const dealii::Vector<double> &y, std::vector<double> &applied,
                  std::vector<double> &dissipative) const;
  void build_element_indices();
  unsigned int body_index(const Body &b) const;
  // Element residuals, into local rows (ElementIndices::rows order)
  void body_residual(unsigned int b, double t, const dealii::Vector<double> &y, const dealii::Vector<double> &yp,
                     std::vector<double> &out) const;
  void joint_residual(unsigned int j, double t, const dealii::Vector<double> &y, const dealii::Vector<double> &yp,
                      std::vector<double> &out) const;
  void force_residual(unsigned int f, double t, const dealii::Vector<double> &y, std::vector<double> &out) const;
  /// Phi_q of a joint's active rows w.r.t. the q entries of its columns (analytic, from B).
  void joint_position_jacobian(unsigned int j, const dealii::Vector<double> &y, const JointEvaluation &e,
                               dealii::FullMatrix<double> &Phi_q) const;
  void add_local(const std::vector<unsigned int> &rows, const std::vector<unsigned int> &cols,
                 const dealii::FullMatrix<double> &block);
  void element_differences(unsigned int kind, unsigned int index, double t, const dealii::Vector<double> &y,
                           const dealii::Vector<double> &yp);
  /// Joint @p j's block from its analytic derivatives (Joint::derivatives), with @p ev its
  /// evaluation at (t, y); false (nothing added) where it has none.
  bool analytic_joint_block(unsigned int j, double t, const dealii::Vector<double> &y, const JointEvaluation &ev);
  /// The same for force @p f (Force::derivatives).
  bool analytic_force_block(unsigned int f, double t, const dealii::Vector<double> &y);
  /// Body @p b's rows of the Jacobian, analytic (Body::equation_jacobians).
  void body_jacobian(unsigned int b, double alpha, const dealii::Vector<double> &y, const dealii::Vector<double> &yp);
  /// The Jacobian's terms in y' (times alpha): into the solver, or, during
  /// assemble_jacobian_parts, unscaled into its dense array.
  void add_derivative_term(unsigned int row, unsigned int col, double alpha, double value);
  std::vector<double> *derivative_terms = nullptr; ///< set during assemble_jacobian_parts only

  Vector3 g;
  std::vector<BodySlot> bodies;
  std::vector<JointSlot> joints;
  std::vector<ForceSlot> forces;
  std::vector<DroppedEquation> dropped;
  std::vector<double> equation_scale; ///< s_r per row of constraint_rows(true)
  unsigned int nq = 0, nv = 0, nlambda = 0, nmu = 0, n_own_q = 0;
  bool finalized = false;
  std::vector<ElementIndices> body_elements, joint_elements, force_elements;
  std::unique_ptr<JacobianSolver> solver;
  std::vector<char> held_limit, held_velocity; ///< per limit, per velocity coordinate
  double impact_energy = 0;
  /// Joint and local limit index of limit @p i.
  std::pair<unsigned int, unsigned int> limit_owner(unsigned int i) const;
  /// The push of the stop that holds own coordinate @p coordinate of joint @p j: B^T lambda - Q
  /// along it, what the free force balance leaves [N].
  double stop_force(unsigned int j, unsigned int coordinate, double t, const dealii::Vector<double> &y) const;
  unsigned long jacobian_count = 0;
  bool element_differences_only = false, newton_matrix = false;
};
} // namespace flextrack::multibody
