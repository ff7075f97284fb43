// The joint interface: everything the index-2 (GGL) DAE needs of a constraint.
//
// A joint touches two bodies (either may be the ground) through markers and may own extra
// coordinates (a track joint's arc length s). It gives, at positions q and time t,
//   Phi(q, t)             its m constraint values,
//   B = dPhi/dq T(q)      their Jacobian w.r.t. the velocity coordinates of each body it touches
//                         and w.r.t. its own coordinates (whose T is the identity),
//   Phi_t = dPhi/dt       the explicit time derivative (drivers).
// The position-level Jacobian Phi_q follows from B (System does it: the Euler-parameter columns
// are 2 B_omega G(p) / |p|^2, because A(p) is computed from p / |p|, so Phi does not change
// along p). Reactions: the generalised constraint force on the bodies is -B^T lambda.
#pragma once

#include <multibody/body.h>
#include <multibody/marker.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace flextrack::multibody
{
struct JointEvaluation
{
  dealii::Vector<double> phi, phi_t;           ///< m values [m or -], [per s]
  std::vector<dealii::FullMatrix<double>> B;   ///< per body of bodies(): m x n_v(body)
  dealii::FullMatrix<double> B_own;            ///< m x n_own_coordinates()
};

/// A joint's terms of the DAE residual (System::joint_residual), without B itself: forming B
/// (equations x velocities) cost more than all the products taken with it.
struct JointResidualTerms
{
  dealii::Vector<double> phi;  ///< Phi, all m equations [m or -]
  dealii::Vector<double> rate; ///< B v + Phi_t, all m equations [m/s or 1/s]
  /// B^T lambda and B^T mu: the velocity coordinates of the bodies of bodies() in order, then the
  /// joint's own coordinates. Empty where no multipliers were given.
  std::vector<double> force_lambda, force_mu;
};

/// Second derivatives of a joint, for the DAE Jacobian (system_jacobian.cc). Rows run over the
/// velocity coordinates v of the bodies of bodies() in order (the ground has none), then the
/// joint's own coordinates; columns over their position coordinates q = (R, p, eta), then the
/// joint's own coordinates. B here is the whole of it: the bodies' blocks and B_own.
struct JointDerivatives
{
  dealii::FullMatrix<double> lambda_q; ///< d(B^T lambda)/dq at fixed lambda
  dealii::FullMatrix<double> mu_q;     ///< d(B^T mu)/dq at fixed mu
  dealii::FullMatrix<double> rate_q;   ///< d(B v + Phi_t)/dq at fixed v: m rows
};

class Joint
{
public:
  explicit Joint(std::string name) : joint_name(std::move(name)) {}
  virtual ~Joint() = default;
  const std::string &name() const { return joint_name; }
  /// What the run's log should say of this joint as the scene placed it (a slider held off its
  /// track, issue 25 item 4), "" if nothing.
  const std::string &note() const { return joint_note; }
  void set_note(std::string text) { joint_note = std::move(text); }
  /// Appends a sentence to the note ("; " between sentences).
  void add_note(const std::string &text) { joint_note += (joint_note.empty() || text.empty() ? "" : "; ") + text; }

  virtual unsigned int n_equations() const = 0;
  /// The bodies it touches, in a fixed order (the first is the one the reaction acts on).
  virtual std::vector<const Body *> bodies() const = 0;
  virtual unsigned int n_own_coordinates() const { return 0; }
  virtual void initial_own_coordinates(double * /*q*/, double * /*v*/) const {}
  /// @p q: coordinates of each body of bodies() (nullptr for the ground).
  virtual void evaluate(const std::vector<const double *> &q, const double *own_q, double t,
                        JointEvaluation &e) const = 0;
  /// Phi, B v + Phi_t and, if @p lambda and @p mu are given (all m equations; dropped ones
  /// zero), B^T lambda and B^T mu (JointResidualTerms). @p v: velocities of each body of bodies()
  /// (nullptr for the ground); @p own_v: the own coordinates' rates.
  virtual void residual_terms(const std::vector<const double *> &q, const double *own_q, double t,
                              const std::vector<const double *> &v, const double *own_v, const double *lambda,
                              const double *mu, JointResidualTerms &r) const = 0;
  /// Second derivatives (JointDerivatives) for multipliers @p lambda and @p mu (all m equations;
  /// dropped ones zero), body velocities @p v (per body of bodies(), nullptr for the ground) and
  /// own velocities @p own_v. Returns false where the joint has none (the system then takes
  /// central differences of the joint's whole residual): the default.
  virtual bool derivatives(const std::vector<const double *> & /*q*/, const double * /*own_q*/, double /*t*/,
                           const double * /*lambda*/, const double * /*mu*/, const std::vector<const double *> & /*v*/,
                           const double * /*own_v*/, JointDerivatives & /*d*/) const
  {
    return false;
  }
  /// Phi_t alone (all m equations; zero where not driven): what the power of the drivers'
  /// reactions needs at every step (Monitors). The default evaluates everything.
  virtual void driver_rates(const std::vector<const double *> &q, const double *own_q, double t,
                            dealii::Vector<double> &phi_t) const
  {
    thread_local JointEvaluation e;
    evaluate(q, own_q, t, e);
    phi_t = e.phi_t;
  }
  /// Short description of equation @p k, e.g. "translation along x of marker 2".
  virtual std::string equation_name(unsigned int k) const { return "equation " + std::to_string(k); }
  /// Is equation @p k rheonomic (a driver): its reaction does work.
  virtual bool is_driver_equation(unsigned int) const { return false; }
  /// Generalised forces on the joint's own coordinates at own positions @p own_q and rates
  /// @p own_v (a track contact's tangential drive force and viscous friction [N]), split into the
  /// applied part (its work counts as applied) and the dissipative part (its work is dissipated).
  /// Each is an array of n_own_coordinates(); both start at zero.
  virtual void own_forces(const double * /*own_q*/, const double * /*own_v*/, double /*t*/, double * /*applied*/,
                          double * /*dissipative*/) const
  {}
  /// Limits of the own coordinates: functions that are positive while the joint is valid (a
  /// track contact: s and L - s). The integrator stops where one reaches zero.
  virtual unsigned int n_limits() const { return 0; }
  virtual void limits(const double * /*own_q*/, double * /*g*/) const {}
  /// What limit @p k does when it is reached. Default: the run stops with limit_report().
  /// An end stop instead holds the own coordinate @p coordinate at its lower (@p upper false) or
  /// upper end: an impact with restitution coefficient e (s'+ = -e s'-), and a rebound slower
  /// than @p hold_speed [m/s] is held there until the stop would have to pull.
  struct EndStop
  {
    bool stop_run = true;
    unsigned int coordinate = 0; ///< index among the joint's own coordinates
    bool upper = false;
    double restitution = 0;
    double hold_speed = 0;
  };
  virtual EndStop end_stop(unsigned int /*k*/) const { return {}; }
  /// One sentence on limit @p k reached at own coordinates @p own_q, rates @p own_v.
  virtual std::string limit_report(unsigned int k, const double * /*own_q*/, const double * /*own_v*/) const
  {
    return "joint '" + name() + "' reached its limit " + std::to_string(k);
  }
  /// Force [N] and torque [N m] (global) that the joint exerts on the first body at its marker,
  /// for multipliers @p lambda (all m equations; dropped ones zero).
  virtual void reaction(const std::vector<const double *> &q, const double *own_q, double t, const double *lambda,
                        Vector3 &force, Vector3 &torque) const = 0;

private:
  std::string joint_name, joint_note;
};
} // namespace flextrack::multibody
