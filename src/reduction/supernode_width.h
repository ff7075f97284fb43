// Narrower supernodes for a CHOLMOD supernodal factor, to keep its memory down.
//
// CHOLMOD stores each supernode of L as one dense column-major block, rows x columns, whose top
// is the square diagonal block: its strictly upper half is stored but holds nothing. For a 3D
// solid the widest supernodes are the nested-dissection separators, thousands of columns wide,
// so that unused half is about a sixth of the factor (10 of 59 million numbers at 7.4e4 dofs).
// Splitting a supernode into pieces of at most w columns leaves the non-zero pattern of L as it
// was, and its numbers to round-off (the updates are summed in another order); the unused part
// shrinks by the number of pieces.
#pragma once

#include <cholmod.h>

#include <cstddef>

namespace flextrack::reduction
{
/// What cap_supernode_width() changed (reported by the tests).
struct SupernodeSplit
{
  std::size_t supernodes_before = 0, supernodes_after = 0;
  std::size_t numbers_before = 0, numbers_after = 0; ///< L->xsize: doubles of the numeric factor
};

/// Splits every supernode of the symbolic supernodal factor @p L (int indices, real, after
/// cholmod_analyze and before cholmod_factorize) that is wider than @p max_width columns into
/// pieces of nearly equal width, and updates the sizes by which CHOLMOD's numeric factorisation
/// and solves allocate (xsize, ssize, maxcsize, maxesize). A piece's rows are the rows of the
/// supernode from its first column on. A simplicial factor is left as it is.
/// Throws std::bad_alloc if CHOLMOD cannot allocate the new index arrays (@p L is then
/// unchanged), std::invalid_argument for a factor with long indices or numbers already.
SupernodeSplit cap_supernode_width(cholmod_factor &L, std::size_t max_width, cholmod_common &common);

/// CHOLMOD's workspace sizes of a supernodal factor: the largest update matrix one supernode
/// sends to one ancestor (maxcsize, in numbers) and the most rows below a diagonal block
/// (maxesize).
struct SupernodeWorkspace
{
  std::size_t max_update = 1, max_rows_below = 1;
};
SupernodeWorkspace supernode_workspace(const cholmod_factor &L);
} // namespace flextrack::reduction
