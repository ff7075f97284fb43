// Redundant joint equations, decided on a neighbourhood of the start (issue 23).
//
// A closed loop has more joint equations than it removes degrees of freedom: a planar four-bar
// built from revolute joints in 3D has 20 equations of rank 17 *everywhere* on its motion, so
// three of them follow from the others and are dropped (their reactions are then not unique).
// The rank of the Jacobian B at the start alone cannot tell this apart from a *singular*
// configuration, where B loses rank at that one point only: a slider-crank whose guide is turned
// so that crank and rod reach it in line (a dead point), a four-bar with all links collinear.
// There an equation looks dependent, but a step away it is not: dropping it lets the bodies leave
// the joint (the slider left its guide, x = 0.4 -> -0.39 m in 0.5 s). So an equation is dropped
// only if it is dependent at the start *and* at configurations nearby that satisfy every joint
// equation:
//
//  1. Scales. Lengths are measured in the scene's length scale L (the largest distance between
//     body-frame origins, the ground's included, or radius of gyration of a body about its
//     frame origin): the velocity coordinates x are scaled to x~ = D^-1 x (translations and
//     arc lengths / L, rotations in rad, modal coordinates by the modal mass: a unit step moves
//     a body by about L), and each equation by the norm s_r of its row of B D at the start, so
//     that B~ = S^-1 B D has rows of unit norm and Phi_r / s_r is a dimensionless residual.
//  2. At the start: the rows of B~, in joint order, are orthogonalised (dependent_rows: modified
//     Gram-Schmidt); a row whose remainder is below 1e-8 of its norm depends on earlier rows.
//  3. Nearby: from the start, steps of 1e-3 (x~) along random directions of the null space of B~
//     (first-order motions the joints allow), each projected back onto Phi = 0 (every equation,
//     Gauss-Newton with the pseudo-inverse of B~). On a regular part of the motion the step
//     returns by O(1e-3 x curvature) only, and the same rows depend on the others there.
//  4. Singular start (an InputError, exit status 2, naming the joints of the loop): the
//     projection does not converge, or returns by more than half the step (the first-order
//     motion is not a motion of the mechanism: it is locked there, as a fully stretched four-bar),
//     or the dependent rows differ between the start and a configuration nearby (branches cross
//     there, as a parallelogram with its links in line). The joints named are those of the
//     dependent rows and of the rows they depend on at the start (the loop).
//  Otherwise the rows dependent at the configurations nearby (those at the start, unless the
//  start is special for the choice of rows only) are dropped.
//
// During the run the dropped equations are watched (System::dropped_equation_margin): they hold
// as long as the motion stays where they depend on the others; where they stop holding, the run
// ends with a report (multibody/end_stops.h).
#pragma once

#include <multibody/system.h>

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <utility>
#include <vector>

namespace flextrack::multibody
{
struct RedundancySettings
{
  double rank_tolerance = 1e-8;  ///< relative remainder below which a row is dependent
  double step = 1e-3;            ///< size of the steps to the configurations nearby (in x~, i.e. of L)
  unsigned int neighbours = 4;   ///< configurations nearby
  double return_limit = 0.5;     ///< a projection that returns by more than this part of the step: locked
  double projection_tolerance = 1e-12; ///< max |Phi_r| / s_r of the projection
  unsigned int max_iterations = 50;
};

struct RedundancyAnalysis
{
  std::vector<std::pair<unsigned int, unsigned int>> redundant; ///< (joint, equation) to drop
  std::vector<double> equation_scales; ///< s_r of every equation (rows of System::constraint_rows(true))
  double length_scale = 1;             ///< L [m]
  unsigned int neighbours_checked = 0; ///< configurations nearby where the rank was compared
};

/// The rows of @p B (in order) that depend on earlier rows: remainder after orthogonalisation
/// against the earlier independent rows (modified Gram-Schmidt, twice) below @p rank_tolerance
/// of the row's norm. @p basis (optional) receives the orthonormal basis of the row space.
std::vector<unsigned int> dependent_rows(const dealii::FullMatrix<double> &B, double rank_tolerance,
                                         std::vector<dealii::Vector<double>> *basis = nullptr);

/// The scene's length scale at @p y [m]: the largest distance between two body-frame origins
/// (the ground's at 0 included) or radius of gyration of a body about its frame origin; 1 if
/// there is none.
double scene_length_scale(const System &system, const dealii::Vector<double> &y);

/// Decides which joint equations of @p system at the assembled configuration @p y (every
/// equation holds) are redundant, as above. Throws InputError (entry Multibody/Joints) if the
/// start is a singular configuration.
RedundancyAnalysis find_redundant_equations(const System &system, double t0, const dealii::Vector<double> &y,
                                            const RedundancySettings &settings = {});
} // namespace flextrack::multibody
