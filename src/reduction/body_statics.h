// Static load cases of a flexible body solved twice (issue 12 item 3): with the full FE model
// (K u = f in the body dofs, reduction/static_solver.h) and with the reduced body
// (K_r eta = Phi^T f, u_r = Phi eta), so that a user sees at every requested place how well the
// reduced basis represents that load. The two use the same load vector f, so the difference is
// the basis's alone.
//
// Which structure is solved: a supported body as it is; a free body reduced by Craig-Bampton
// held at its first interface (the body frame, where every vector of the basis is zero). A free
// body reduced with free interfaces has a mean-axis frame and no static solution without
// inertia relief: refused.
//
// Loads (fem/load_case.h, places 'ARM S' or an interface / output point): point forces and
// moments on arms are consistent nodal loads (between nodes too, like a sliding contact);
// on interfaces and output points they act on the point's six dofs; line loads on arms; node set
// forces and moments on the body's solid; gravity is M_full g (the consistent mass of every part and the
// point masses, times the rigid translation g).
#pragma once

#include <fem/body_model.h>
#include <fem/load_case.h>
#include <reduction/component_modes.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::reduction
{
class StaticSolver;

/// u [m] and theta [rad] (global axes) at a place of the body.
using PlaceValues = std::array<double, 6>;

struct BodyStaticCase
{
  std::string name;
  std::vector<PlaceValues> full, reduced; ///< one per report place
  double strain_energy_full = 0, strain_energy_reduced = 0; ///< [J]
  double residual = 0; ///< max |K u - f| / max |f| of the full solve
  /// |u_r - u| / |u| at place @p k (displacement and rotation separately; absolute where u = 0).
  double displacement_difference(unsigned int k) const;
  double rotation_difference(unsigned int k) const;
};

class BodyStatics
{
public:
  /// @p basis: reduce(model, settings). InputError for a free body without a body frame.
  BodyStatics(const fem::BodyModel &model, const ReducedBasis &basis, const ReductionSettings &settings);
  ~BodyStatics();

  /// The load vector of @p load_case in body dofs.
  dealii::Vector<double> load_vector(const fem::LoadCase &load_case) const;
  /// Every case solved with the full and the reduced model, values at @p places.
  std::vector<BodyStaticCase> solve(const std::vector<fem::LoadCase> &cases,
                                    const std::vector<fem::LoadPoint> &places) const;
  /// u and theta at @p place of the body-dof vector @p y (expanded to full dofs @p x).
  PlaceValues values_at(const fem::LoadPoint &place, const dealii::Vector<double> &y,
                        const dealii::Vector<double> &x) const;
  /// The constrained body dofs of the full solve (the body frame of a free body), for tests.
  unsigned int n_held_dofs() const { return held.n_constraints(); }

private:
  /// u = Phi K_r^{-1} Phi^T f.
  dealii::Vector<double> reduced_solution(const dealii::Vector<double> &f, double &strain_energy) const;

  const fem::BodyModel &model;
  const ReducedBasis &basis;
  dealii::AffineConstraints<double> held;
  std::unique_ptr<StaticSolver> full_solver;
};

/// The default report places of a body: every interface and output point, then the places of
/// the point loads of @p cases (each once).
std::vector<fem::LoadPoint> default_body_places(const fem::Body &body, const std::vector<fem::LoadCase> &cases);
} // namespace flextrack::reduction
