// Narrower supernodes for a CHOLMOD supernodal factor, to keep its memory down.
//
// CHOLMOD stores each supernode of L as one dense column-major block, rows x columns, whose top
// is the square diagonal block: its strictly upper half is stored but holds nothing. For a 3D
// solid the widest supernodes are the nested-dissection separators, thousands of columns wide,
// so that unused half is about a sixth of the factor (10 of 59 million numbers at 7.4e4 dofs).
// Splitting a supernode into pieces of at most w columns leaves the non-zero pattern of L, and
// so the factor's numbers, as they were; the unused part shrinks by the number of pieces.
#pragma once

#include <cholmod.h>

#include <cstddef>

namespace flextrack::reduction
{
/// What cap_supernode_width() changed, for the log and the tests.
struct SupernodeSplit
{
  std::size_t supernodes_before = 0, supernodes_after = 0;
  std::size_t numbers_before = 0, numbers_after = 0; ///< L->xsize: doubles of the numeric factor
};

/// Splits every supernode of the symbolic supernodal factor @p L (after cholmod_analyze, before
/// cholmod_factorize) that is wider than @p max_width columns into pieces of nearly equal width,
/// and updates the sizes CHOLMOD's numeric factorisation and solves allocate by (xsize, ssize,
/// maxcsize, maxesize). A piece's rows are the rows of the supernode from its first column on.
/// Throws std::bad_alloc if CHOLMOD cannot allocate the new index arrays; @p L is then unchanged.
SupernodeSplit cap_supernode_width(cholmod_factor &L, std::size_t max_width, cholmod_common &common);
} // namespace flextrack::reduction
