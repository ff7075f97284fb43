// Static load cases of a scene: named sets of loads that 'flextrack static' applies one at a
// time to the FE model (one factorisation of K for all of them).
//
// A scene lists its load cases in "Static/Load cases" and describes each in its own
// "subsection Load case NAME" (the two-pass pattern of io/scene_file.h):
//   subsection Static
//     set Load cases = tip, weight
//     set Points     = 1.5, 3        # arm: arc lengths [m] where u and theta are reported
//   end
//   subsection Load case tip
//     set Point forces  = 3: 0 -100 0          # S [m]: Fx Fy Fz [N], global axes
//     set Point moments = 3: 0 0 20            # S [m]: Mx My Mz [N m]
//     set Line loads    = 0 1.5: 0 -10 0       # S0 S1 [m]: qx qy qz [N/m] on S0 <= s <= S1
//     set Gravity       = 0, 0, -9.81          # [m/s^2], acts on the density of the material
//     set Node set forces = XMAX: 0 0 -100     # solid: total force [N] on a node set
//     set Node set moments = XMAX: 10 0 0      # solid: moment [N m] about the set's centroid
//     set Node forces = XMAX: 0 0 -10          # solid: force [N] on every node of a set
//     set Pressures = XMAX: 1e6                # solid: pressure [Pa] on the set's faces
//     set Support displacements = 0: 0 0 -1e-3 # arm: S: ux uy uz [theta]; solid: SUPPORT: ux uy uz
//   end
// In a body scene ('Model = body') a point load acts at 'ARM S' (an arm of the body and an arc
// length on it) or at 'NAME' (an interface or output point of the body), a line load on
// 'ARM S0 S1'; Static/Points lists such places too.
// The load vectors themselves are built by the FE models (CurvedBeamModel::add_point_load, ...),
// the exact resultant of the loads (for the equilibrium check) here.
#pragma once

#include <fem/arm.h>
#include <fem/body.h>
#include <fem/solid.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/tensor.h>

#include <string>
#include <vector>

namespace flextrack::fem
{
/// Most load cases of a scene, and most items in one entry of a load case.
constexpr unsigned int max_load_cases = 1000;
constexpr unsigned int max_load_items = 1000;

/// A place on an arm scene's arm (arc length s [m]) or on a body: arc length s on the body's arm
/// number 'arm', or the body's interface or output point called 'point'.
struct LoadPoint
{
  double s = 0;
  unsigned int arm = 0; ///< index in Body::arms (0 in an arm scene)
  std::string point;    ///< a body's interface or output point; empty: (arm, s)
  std::string label;    ///< as the user wrote it, for the report ("boom 0.35", "tip", "s = 1.5 m")
};

/// A force [N] or moment [N m] at a LoadPoint (an arm's arc length s [m]), global axes.
struct ArmPointLoad : LoadPoint
{
  dealii::Tensor<1, 3> value;
};

/// A uniform distributed force q [N/m] (global axes) on s0 <= s <= s1 [m] of an arm (a body's
/// arm number 'arm').
struct ArmLineLoad
{
  double s0 = 0, s1 = 0;
  unsigned int arm = 0;
  dealii::Tensor<1, 3> q;
};

/// A total force [N] (global axes) on the nodes of a solid's node set: distributed as a uniform
/// traction over the boundary faces whose corners all belong to the set (consistent nodal
/// weights), or in equal shares over the set's nodes if it holds no whole face.
struct NodeSetForce
{
  std::string node_set; ///< upper case
  dealii::Tensor<1, 3> force;
};

/// A force [N] (global axes) on every node of a solid's node set (as CalculiX's *CLOAD on a
/// node set): the total is the number of the set's nodes times the force.
struct NodeForce
{
  std::string node_set; ///< upper case
  dealii::Tensor<1, 3> force;
};

/// A moment [N m] (global axes) on a solid's node set, about the centroid of the set's boundary
/// faces: carried by the traction t(r) = lambda x r (r from the centroid, J lambda = M with J the
/// faces' area inertia tensor int (|r|^2 1 - r r^T) dA), the smallest traction field with that
/// moment and no resultant force; consistent nodal weights. A set without a whole face: nodal
/// forces lambda x r_i with J summed over the nodes.
struct NodeSetMoment
{
  std::string node_set; ///< upper case
  dealii::Tensor<1, 3> moment;
};

/// A pressure p [Pa] on the boundary faces of a solid's node set (the faces whose corners all
/// belong to the set): the traction -p n with n the outward normal, so p > 0 pushes on the
/// faces; consistent nodal weights on the curved 20-node faces.
struct NodeSetPressure
{
  std::string node_set; ///< upper case
  double pressure = 0;
};

/// A prescribed displacement of a support (non-zero support displacement, e.g. a settlement):
/// an arm scene's support at arc length s gets u [m] (three values; a clamped support may also
/// take the rotation theta [rad], six values); a solid scene's support (a node set or a plane of
/// Solid/Supports) gets u [m] in the components it fixes. Global axes.
struct SupportDisplacement
{
  double s = 0;             ///< arm: the support's arc length [m]
  std::vector<unsigned int> supports; ///< solid: indices in Solid::supports of every support at that place
  std::vector<double> value; ///< 3 (u) or 6 (u, theta) numbers
  std::string label;        ///< as written, for messages
};

/// Force [N] and moment [N m] about the origin of a system of loads (or reactions).
struct Resultant
{
  dealii::Tensor<1, 3> force, moment;
};

struct LoadCase
{
  std::string name;
  std::vector<ArmPointLoad> point_forces, point_moments;
  std::vector<ArmLineLoad> line_loads;
  std::vector<NodeSetForce> node_set_forces;
  std::vector<NodeSetMoment> node_set_moments;
  std::vector<NodeForce> node_forces;
  std::vector<NodeSetPressure> pressures;
  std::vector<SupportDisplacement> support_displacements;
  dealii::Tensor<1, 3> gravity; ///< [m/s^2]

  /// Declares "subsection Load case NAME" for each of @p names.
  static void declare_parameters(dealii::ParameterHandler &prm, const std::vector<std::string> &names);
  /// Reads "subsection Load case @p name"; the arc lengths are checked against @p arm, the node
  /// sets against @p solid (either null where the scene has none: then its loads are refused);
  /// with @p body (a body scene; @p arm null) the places are 'ARM S' or an interface / output
  /// point, the node sets those of the body's solid. InputError naming the entry.
  static LoadCase parse_parameters(dealii::ParameterHandler &prm, const std::string &name, const Arm *arm,
                                   const Solid *solid = nullptr, const Body *body = nullptr);

  /// The exact resultant about the origin of the loads of this case on @p arm (point loads at
  /// their curve points, line loads and gravity integrated along the exact centre line).
  Resultant resultant_on(const Arm &arm) const;
};

/// @p arm with a mesh node at every point load, line-load end of @p cases and every point of
/// @p points [m] (added as 'free' supports, which only place a node).
Arm with_load_stations(const Arm &arm, const std::vector<LoadCase> &cases, const std::vector<double> &points);

/// "subsection Static": which load cases a scene has and where results are reported.
struct StaticSettings
{
  std::vector<std::string> load_cases;
  std::vector<double> points; ///< arm: arc lengths [m]; empty = the end of the arm
  std::vector<LoadPoint> body_points; ///< body: 'ARM S' or interface / output points; empty: see static_command
  std::vector<std::string> node_sets; ///< solid: mean displacement reported; empty = the loaded sets
  std::string solver = "auto"; ///< "direct", "iterative" (solids: CG with algebraic multigrid) or "auto"
  /// Solids above this many dofs are solved iteratively with 'auto'.
  static constexpr unsigned int iterative_above_dofs = 100000;
  double tolerance = 1e-10;           ///< iterative: relative residual of each CG solve

  /// "Static/Load cases" alone (first pass of a scene, io/scene_file.cc).
  static void declare_load_case_list(dealii::ParameterHandler &prm);
  static std::vector<std::string> parse_load_case_list(dealii::ParameterHandler &prm);
  static void declare_parameters(dealii::ParameterHandler &prm);
  /// @p arm, @p solid, @p body: the structure of the scene (checks the points, node sets), or null.
  static StaticSettings parse_parameters(dealii::ParameterHandler &prm, const Arm *arm, const Solid *solid = nullptr,
                                         const Body *body = nullptr);
};
} // namespace flextrack::fem
