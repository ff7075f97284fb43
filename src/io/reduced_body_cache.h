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

#include <functional>
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
/// @p before_reduction, if given, is called just before the body is reduced, i.e. only when the
/// cache cannot serve it - which is known only once the cached file has been read and checked in
/// full (a damaged file with the right input hash is reduced again). InputError (naming the
/// scene's file) for bad input, SolverError for solver failures.
ObtainedBody cached_or_reduced_body(const BodyScene &scene, const std::string &file, std::ostream &log,
                                    dealii::TimerOutput &timer, const std::function<void()> &before_reduction = {});
} // namespace flextrack::io
