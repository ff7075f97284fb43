// Physical plausibility of a reduced body (issue 23, item 4): the properties every reduced body
// of a real elastic body has, whatever the mesh, the method or the number of modes, checked
// when a reduced body file is read (and before one is written), so that a damaged or crafted
// file (mass -1 kg, an all-zero mass matrix, -K, K[0,1] = 1e12, damping -100 I) is refused
// instead of simulated:
//   - M = Phi^T M Phi symmetric positive definite: the kinetic energy of every modal velocity
//     is positive (the modes are independent);
//   - K = Phi^T K Phi symmetric positive semi-definite: no motion releases elastic energy. Zero
//     eigenvalues are allowed: a mechanism that the supports and ties leave free has them (seen
//     in tests/badinput/numeric_entries.py: an interface placed where it holds nothing), as
//     would a basis from another tool that spans the rigid-body motions of a free body;
//   - the symmetric part of the damping matrix positive semi-definite: no motion gains energy
//     from damping (a skew part is gyroscopic and does no work);
//   - frequencies non-negative (within the round-off of a zero eigenvalue, as for K);
//   - mass positive, the inertia tensor about the origin symmetric with positive principal
//     moments that satisfy the triangle inequality J1 + J2 >= J3, and the inertia tensor about
//     the centre of mass (from mass, first moment and J_O) positive semi-definite and obeying
//     the same inequality: every real mass distribution does (J3 = int rho (x1^2 + x2^2) <=
//     J1 + J2 = int rho (x1^2 + x2^2 + 2 x3^2), in principal axes).
// The tolerances are round-off bounds (below, with their reasons); what they let through is
// damage far too small to matter physically, which the content checksum of the file catches.
#pragma once

#include <reduction/reduced_body.h>

namespace flextrack::reduction
{
/// Relative tolerance of symmetry: |A_ij - A_ji| <= symmetry_tolerance max |A|. The reduced
/// matrices are products Phi^T A Phi in double precision, symmetric to round-off, about n eps
/// max |A| (1e-13 for n = 300 modes); 1e-8 leaves five orders of margin, and an asymmetry that
/// large is still far below anything that changes a motion visibly.
inline constexpr double symmetry_tolerance = 1e-8;
/// Relative tolerance of semi-definiteness: smallest eigenvalue >= -tolerance * (largest
/// eigenvalue magnitude). Zero eigenvalues (rigid-body motions) come out of Phi^T K Phi as round-
/// off, about n eps times the largest eigenvalue, times the conditioning of the basis.
inline constexpr double semidefinite_tolerance = 1e-8;
/// Positive definiteness of M: smallest eigenvalue > tolerance * largest. A mass matrix whose
/// condition number exceeds 1e12 belongs to numerically dependent modes (and no integrator
/// could solve with it in double precision); a valid body's is 1 to round-off, its basis being
/// M-orthonormal (tests/unit/plausibility_test.cc).
inline constexpr double definite_tolerance = 1e-12;

/// Throws std::runtime_error naming the first property of the list above that @p body does
/// not have, with the offending number and unit, e.g. "the reduced mass matrix (/reduced/mass)
/// is not positive definite (smallest eigenvalue -3.20e-01 kg, largest 1.00e+00 kg)".
void check_physical_plausibility(const ReducedBody &body);
} // namespace flextrack::reduction
