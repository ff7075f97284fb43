// The inertia invariants of a flexible body computed from its FE model (the builder of the value
// in reduction/inertia_invariants.h, which a multibody run reads without any FE header).
#pragma once

#include <fem/body_model.h>
#include <reduction/inertia_invariants.h>

namespace flextrack::reduction
{
/// The invariants of @p modes (body dofs) of @p body, about the global origin and axes (the body
/// frame of the undeformed body).
InertiaInvariants compute_inertia_invariants(const fem::BodyModel &body, const std::vector<dealii::Vector<double>> &modes);
/// The same from modes already expanded to the full dofs (BodyModel::expand).
InertiaInvariants compute_inertia_invariants_of_expanded(const fem::BodyModel &body,
                                                         const std::vector<dealii::Vector<double>> &full_modes);
} // namespace flextrack::reduction
