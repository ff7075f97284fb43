// The one way to obtain the reduced body of a body scene, for 'flextrack reduce' and for a
// multibody run that names a body scene: a reduced body file whose input hash equals the
// scene's (every parameter but Output, and the bytes of every file a parameter names) is loaded
// and checked in full, nothing recomputed; otherwise the FE model is built and reduced, and the
// result is written to the file atomically.
#pragma once

#include <io/body_scene.h>
#include <io/json.h>
#include <reduction/reduced_body.h>

#include <deal.II/base/timer.h>

#include <ostream>
#include <string>

namespace flextrack::io
{
struct ObtainedBody
{
  reduction::ReducedBody body;
  bool from_cache = false;
  /// Accuracy against the full model ("Reduction/Check modes" > 0 and not from the cache), else empty.
  JsonObject check;
  bool checked = false;
};

/// The reduced body of @p scene: loaded from @p file if it is up to date, else built and written
/// to @p file (its folder must exist). Progress lines go to @p log; stages are timed in @p timer.
/// InputError (naming the scene's file) for bad input, SolverError for solver failures.
ObtainedBody cached_or_reduced_body(const BodyScene &scene, const std::string &file, std::ostream &log,
                                    dealii::TimerOutput &timer);
} // namespace flextrack::io
