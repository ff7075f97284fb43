// Inertia invariants of a reduced flexible body (Shabana, Dynamics of Multibody Systems, ch. 5;
// Wallrapp's SID): volume integrals over the body computed once, from the consistent mass
// matrix, so that time stepping never loops over elements. With x the undeformed position of a
// point (body frame), Phi the mode shapes (translation part) and u = x + Phi eta:
//   m = int rho,  s = int rho x,  J_O = int rho (x.x 1 - x x^T) (+ section rotary inertia)
//   I3 = int rho Phi                      (3 x n)
//   I4 = int rho x~ Phi (+ rotary inertia of arm sections and point masses turning with Phi)
//   P_k = int rho phi_k x^T               (3 x 3 per mode)
//   Q_jk = int rho phi_j phi_k^T          (3 x 3 per pair of modes)
// Each integral int rho a b is a^T M b, with M the consistent mass matrix of the full model and
// a, b translation fields. The terms that are quadratic in the modes (P, Q) take the
// translations only: the rotary inertia of thin arm sections is neglected there (relative size
// (section radius / arm length)^2).
//
// FloatingFrameInertia evaluates, for the coordinates (R, omega, eta) - R the frame origin
// (global), omega the angular velocity in body axes, eta the modal coordinates - the mass matrix
// M(A, eta) and the quadratic-velocity vector Q_v, with M qdd = Q_v + applied forces:
//   M_RR = m 1, M_Rw = -A S~, M_Rf = A I3, M_ww = J(eta), M_wf = int rho u~ Phi, M_ff = Phi^T M Phi
//   Q_R = -A (w~ w~ S + 2 w~ I3 etad)
//   Q_w = -(w~ J w + 2 sum_k etad_k (tr(Ph_k) w - Ph_k w))
//   Q_k = -(w^T Ph_k w - |w|^2 tr(Ph_k) + 2 w . sum_j etad_j I5_jk)
// with S = s + I3 eta, Ph_k = int rho phi_k u^T = P_k + sum_j eta_j Q_kj, I5_jk = int rho phi_j x phi_k.
#pragma once

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <vector>

namespace flextrack::reduction
{
struct InertiaInvariants
{
  double mass = 0;                           ///< m [kg]
  dealii::Tensor<1, 3> first_moment;         ///< s = int rho x [kg m]
  dealii::Tensor<2, 3> inertia_origin;       ///< J_O about the body-frame origin [kg m^2]
  dealii::FullMatrix<double> I3, I4;         ///< 3 x n [kg], [kg m]
  std::vector<dealii::Tensor<2, 3>> P;       ///< n, [kg m]
  std::vector<dealii::Tensor<2, 3>> Q;       ///< n * n, Q[j * n + k] [kg]
  unsigned int n_modes() const { return I3.n(); }

  dealii::Point<3> centre_of_mass() const;                 ///< s / m [m]
  dealii::Tensor<2, 3> inertia_about_centre_of_mass() const; ///< J_O - m (|c|^2 1 - c c^T) [kg m^2]
  /// I5_jk = int rho phi_j x phi_k, from Q.
  dealii::Tensor<1, 3> I5(unsigned int j, unsigned int k) const;
};

class FloatingFrameInertia
{
public:
  /// @p modal_mass: Phi^T M Phi (n x n).
  FloatingFrameInertia(const InertiaInvariants &invariants, const dealii::FullMatrix<double> &modal_mass);
  unsigned int size() const { return 6 + n; }
  /// Mass matrix (6 + n)^2 for rotation matrix @p A (body to global) and modal coordinates @p eta
  /// (n entries; here and below).
  void mass_matrix(const dealii::Tensor<2, 3> &A, const double *eta, dealii::FullMatrix<double> &M) const;
  /// M(A, eta) @p v_dot (6 + n entries each) without forming M: what a residual needs. @p Mv
  /// must not overlap @p v_dot.
  void mass_times(const dealii::Tensor<2, 3> &A, const double *eta, const double *v_dot,
                  double *Mv) const;
  /// Quadratic-velocity vector (6 + n) at (A, eta) with angular velocity @p omega (body axes) and
  /// modal velocities @p eta_dot.
  void quadratic_velocity(const dealii::Tensor<2, 3> &A, const double *eta, const dealii::Tensor<1, 3> &omega,
                          const double *eta_dot,
                          dealii::Vector<double> &Qv) const;

  /// Derivatives of the inertial part of a body's residual, r = M(A, eta) v_dot - Q_v, with respect
  /// to eta, omega and eta_dot (each 6 + n rows), at v_dot = (R'', omega', eta'') (global, body
  /// axes, modal). Its dependence on A is returned through two vectors (body axes): r_R = m R'' +
  /// A h_R and r_omega = S x (A^T R'') + terms free of A, with S = s + I3 eta. Cost O(n^2).
  struct Derivatives
  {
    dealii::FullMatrix<double> d_eta, d_omega, d_eta_dot; ///< (6 + n) x n, (6 + n) x 3, (6 + n) x n
    dealii::Tensor<1, 3> h_R, S;
  };
  void derivatives(const dealii::Tensor<2, 3> &A, const double *eta, const dealii::Tensor<1, 3> &omega,
                   const double *eta_dot, const double *v_dot, Derivatives &d) const;

private:
  /// The parts of M and Q_v that depend on eta alone, each O(n^2) to form: S = s + I3 eta,
  /// J(eta), Ph_k = P_k + sum_j eta_j Q_kj and Mwf_k = I4_k + sum_j eta_j I5_jk.
  struct EtaTerms
  {
    dealii::Tensor<1, 3> S;
    dealii::Tensor<2, 3> J;
    std::vector<dealii::Tensor<2, 3>> Ph;
    std::vector<dealii::Tensor<1, 3>> Mwf;
  };
  /// The terms at @p eta. A residual evaluates M and Q_v at the same eta, and the Jacobian
  /// again: each thread keeps the terms of the last eta per inertia, so that they are formed
  /// once (they were 60 % of a 32-mode body's residual).
  const EtaTerms &eta_terms(const double *eta) const;

  unsigned int n;
  /// Tells inertias apart in the per-thread cache of eta_terms() (an address can be reused).
  unsigned long long id;
  InertiaInvariants inv;
  dealii::FullMatrix<double> modal_mass;
  std::vector<dealii::Tensor<1, 3>> i5; // n * n
  /// The sums over j of eta_j Q_kj and eta_j I5_jk as dot products over contiguous rows:
  /// q_rows[(9 k + 3 a + b) n + j] = Q_kj[a][b], i5_rows[(3 k + a) n + j] = I5_jk[a].
  std::vector<double> q_rows, i5_rows;
};
} // namespace flextrack::reduction
