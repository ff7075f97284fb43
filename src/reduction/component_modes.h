// Component mode synthesis of a flexible body (FORMULATION.md sec. 7): a small basis Phi of
// body-dof vectors, so that the body's elastic displacement is u = Phi eta.
//
// Methods (chosen per body, "subsection Reduction"):
//  - Craig-Bampton (Craig & Bampton 1968): normal modes with every interface clamped, plus the
//    static constraint modes of the interface dofs (unit displacement of one, the others fixed,
//    no load elsewhere). A free body is referred to its first interface, the body frame: that
//    interface stays clamped and has no constraint modes (its constraint modes would be the
//    rigid-body motions, which the floating frame carries).
//  - free interface + residual attachment (MacNeal 1971, Rubin 1975): normal modes of the free
//    (or supported) body plus the static responses to unit loads at the interface dofs. For a
//    free body the loads are balanced by inertia relief, f - M R R^T f, the static solve is
//    anchored at the first interface, and every vector is made M-orthogonal to the rigid-body
//    modes R: the body frame is then a mean-axis (Tisserand) frame, int rho Phi = 0 and
//    int rho x ~ Phi = 0.
//  - track load modes, added to either method for every arm that carries a sliding contact: the
//    static responses to unit forces along x, y, z at stations s_k = k L / n along the arm
//    (with the interfaces fixed for Craig-Bampton, with inertia relief for a free body).
// The static vectors are M-orthonormalised against the normal modes (Gram-Schmidt twice; a
// vector that is dependent within 1e-8 is dropped) and the basis is finally rotated onto the
// eigenvectors of the reduced problem: Phi^T M Phi = 1, Phi^T K Phi = diag(w_i^2).
#pragma once

#include <fem/body_model.h>
#include <reduction/modal_solver.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace flextrack::reduction
{
struct ReductionSettings
{
  enum class Method { craig_bampton, free_interface };
  Method method = Method::craig_bampton;
  unsigned int n_normal_modes = 20;      ///< normal modes (fixed- or free-interface) [-]
  std::vector<std::string> track_arms;   ///< arms that carry a sliding contact
  unsigned int n_stations = 8;           ///< load stations per track arm [-]
  double damping_ratio = 0;              ///< modal damping ratio of every reduced mode [-]
  double rayleigh_mass = 0;              ///< Rayleigh alpha [1/s]: C += alpha M
  double rayleigh_stiffness = 0;         ///< Rayleigh beta [s]: C += beta K
  ModalSettings modal;                   ///< eigen solver settings (tolerance, direct solver)
  unsigned int n_check_modes = 0;        ///< compare this many frequencies with the full model [-]
  bool geometric_stiffness = false;      ///< compute the geometric stiffness of inertial loads

  static void declare_parameters(dealii::ParameterHandler &prm);
  /// Reads "subsection Reduction" (and the eigen solver settings of "Modal analysis").
  static ReductionSettings parse_parameters(dealii::ParameterHandler &prm);
  std::string method_name() const;
};

struct ReducedBasis
{
  std::vector<dealii::Vector<double>> modes; ///< body dofs; Phi^T M Phi = 1, Phi^T K Phi diagonal
  dealii::FullMatrix<double> stiffness, mass, damping; ///< Phi^T K Phi, Phi^T M Phi, C (SI units)
  unsigned int n_normal = 0;    ///< normal modes that went in
  unsigned int n_interface = 0; ///< constraint or residual attachment vectors kept
  unsigned int n_track = 0;     ///< track load vectors kept
  /// Per arm of the body: the stations where track loads were applied (0: not a track arm).
  std::vector<unsigned int> track_stations;
  unsigned int n_dropped = 0;   ///< static vectors dropped as dependent
  /// The factor of the clamped body on the process that holds most of it, estimated before it
  /// was made [bytes] (0 if none was made).
  double factor_bytes = 0;
  /// What the process that held most held when the factorisation started [bytes].
  double held_before_factor_bytes = 0;
  std::vector<double> frequencies_hz() const; ///< of the reduced model, ascending
  /// Geometric stiffness of the 12 unit inertial load cases (empty unless asked for), each n x n:
  /// 0-5 centrifugal, W = omega omega^T = e_x e_x^T, e_y e_y^T, e_z e_z^T, e_x e_y^T + e_y e_x^T,
  /// e_x e_z^T + e_z e_x^T, e_y e_z^T + e_z e_y^T; 6-8 acceleration e_x, e_y, e_z of the frame
  /// origin; 9-11 angular acceleration e_x, e_y, e_z (all in body axes). Only the arms carry
  /// geometric stiffness (their axial force); solid parts are taken as stiff.
  std::vector<dealii::FullMatrix<double>> geometric_stiffness;
};

/// A reduction method: one row of the central table reduction_methods(). The two methods of
/// FlexTrack differ in one choice, whether the interfaces are held fixed for the normal modes
/// (then the static vectors are constraint modes) or left free (then they are residual
/// attachment modes); the steps of reduce() read that choice from the row.
struct ReductionMethod
{
  ReductionSettings::Method method;
  std::string name;        ///< the value of Reduction/Method
  std::string title;       ///< for messages
  std::string description; ///< for print-parameters
  bool fixed_interface;
};
const std::vector<ReductionMethod> &reduction_methods();
const ReductionMethod &reduction_method(ReductionSettings::Method method);

/// Reduce @p body; the stages are timed in @p timer if given. Throws InputError for impossible
/// requests (more modes than dofs, a free body without an interface to refer it to, an unknown
/// track arm) and SolverError for failures.
ReducedBasis reduce(const fem::BodyModel &body, const ReductionSettings &settings, dealii::TimerOutput *timer = nullptr);

/// The @p n lowest frequencies [Hz] of the full FE model that the reduced model approximates:
/// the supported body; a free body held at its first interface (Craig-Bampton: the body frame);
/// the elastic modes of a free body (free-interface). The baseline of accuracy checks.
std::vector<double> full_model_frequencies_hz(const fem::BodyModel &body, const ReductionSettings &settings,
                                              unsigned int n);
} // namespace flextrack::reduction
