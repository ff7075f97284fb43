// A reduced body collected from a flexible body's FE model and its reduced basis (the builder of
// the value in reduction/reduced_body.h, which consumers read without any FE header).
#pragma once

#include <fem/body_model.h>
#include <reduction/component_modes.h>
#include <reduction/reduced_body.h>

namespace flextrack::reduction
{
/// Collect the reduced body of @p model reduced to @p basis.
ReducedBody make_reduced_body(const fem::BodyModel &model, const ReducedBasis &basis, const std::string &method);
} // namespace flextrack::reduction
