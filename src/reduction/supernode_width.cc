#include <reduction/supernode_width.h>

#include <algorithm>
#include <new>
#include <stdexcept>
#include <utility>
#include <vector>

namespace flextrack::reduction
{
namespace
{
/// An array of @p n ints from CHOLMOD's allocator, which frees L's arrays.
int *cholmod_ints(const std::size_t n, cholmod_common &common)
{
  auto *p = static_cast<int *>(cholmod_malloc(n, sizeof(int), &common));
  if (!p) throw std::bad_alloc();
  return p;
}

/// The pieces of a split factor, in the layout of cholmod_factor's supernodal arrays.
struct Pieces
{
  std::size_t n_super = 0, n_rows = 0, n_numbers = 0;
  int *super = nullptr, *pi = nullptr, *px = nullptr, *rows = nullptr;
};

/// Frees the arrays of @p p that are allocated.
void free_pieces(Pieces &p, cholmod_common &common)
{
  for (int *a : {p.super, p.pi, p.px})
    if (a) cholmod_free(p.n_super + 1, sizeof(int), a, &common);
  if (p.rows) cholmod_free(p.n_rows, sizeof(int), p.rows, &common);
  p.super = p.pi = p.px = p.rows = nullptr;
}

/// Calls use(k, first, end) for each piece [first, end) of the columns of every supernode k of
/// @p L: ceil(width / max_width) pieces of nearly equal width.
template <typename Use>
void for_each_piece(const cholmod_factor &L, const std::size_t max_width, Use &&use)
{
  const auto *super = static_cast<const int *>(L.super);
  for (std::size_t k = 0; k < L.nsuper; ++k)
    {
      const std::size_t width = super[k + 1] - super[k]; // >= 1
      const std::size_t n_pieces = 1 + (width - 1) / max_width;
      std::size_t first = super[k];
      for (std::size_t q = 0; q < n_pieces; ++q)
        {
          const std::size_t end = first + width / n_pieces + (q < width % n_pieces ? 1 : 0);
          use(k, first, end);
          first = end;
        }
    }
}

/// The rows of supernode @p k from column @p first on: [begin, end) in L.s.
std::pair<std::size_t, std::size_t> rows_from(const cholmod_factor &L, const std::size_t k, const std::size_t first)
{
  const auto *super = static_cast<const int *>(L.super), *pi = static_cast<const int *>(L.pi);
  return {pi[k] + (first - super[k]), pi[k + 1]};
}

/// The sizes of the split factor. They are at most those of L (a piece stores no more than its
/// share of the supernode's block), which CHOLMOD has already checked to fit its int indices.
Pieces count_pieces(const cholmod_factor &L, const std::size_t max_width)
{
  Pieces p;
  for_each_piece(L, max_width, [&](std::size_t k, std::size_t first, std::size_t end) {
    const auto [begin, stop] = rows_from(L, k, first);
    ++p.n_super;
    p.n_rows += stop - begin;
    p.n_numbers += (stop - begin) * (end - first);
  });
  return p;
}

/// Allocates and fills the arrays of @p p; on std::bad_alloc nothing stays allocated.
void fill_pieces(const cholmod_factor &L, const std::size_t max_width, Pieces &p, cholmod_common &common)
{
  try
    {
      p.super = cholmod_ints(p.n_super + 1, common);
      p.pi = cholmod_ints(p.n_super + 1, common);
      p.px = cholmod_ints(p.n_super + 1, common);
      p.rows = cholmod_ints(p.n_rows, common);
    }
  catch (const std::bad_alloc &)
    {
      free_pieces(p, common);
      throw;
    }
  const auto *rows = static_cast<const int *>(L.s);
  std::size_t piece = 0, row = 0, number = 0;
  for_each_piece(L, max_width, [&](std::size_t k, std::size_t first, std::size_t end) {
    // The piece's rows: its own columns, then the rest of the supernode's and those below.
    const auto [begin, stop] = rows_from(L, k, first);
    p.super[piece] = first;
    p.pi[piece] = row;
    p.px[piece] = number;
    std::copy(rows + begin, rows + stop, p.rows + row);
    row += stop - begin;
    number += (stop - begin) * (end - first);
    ++piece;
  });
  p.super[p.n_super] = L.n;
  p.pi[p.n_super] = row;
  p.px[p.n_super] = number;
}

/// supernode_workspace() of the supernodal arrays @p super, @p pi, @p rows of an n x n factor.
SupernodeWorkspace workspace_of(const std::size_t n, const std::size_t n_super, const int *super, const int *pi,
                                const int *rows)
{
  // A descendant's rows below its diagonal block fall into its ancestors in runs (the rows are
  // sorted); the run in ancestor s gives an update C of (rows from the run on) x (rows in the run).
  std::vector<int> supernode_of(n);
  for (std::size_t k = 0; k < n_super; ++k)
    std::fill(supernode_of.begin() + super[k], supernode_of.begin() + super[k + 1], k);
  SupernodeWorkspace w;
  for (std::size_t d = 0; d < n_super; ++d)
    {
      const std::size_t end = pi[d + 1];
      std::size_t run = pi[d] + (super[d + 1] - super[d]);
      w.max_rows_below = std::max(w.max_rows_below, end - run);
      while (run < end)
        {
          const int s = supernode_of[rows[run]];
          std::size_t next = run;
          while (next < end && supernode_of[rows[next]] == s) ++next;
          w.max_update = std::max(w.max_update, (end - run) * (next - run));
          run = next;
        }
    }
  return w;
}

/// Frees L's supernodal arrays (with the sizes CHOLMOD allocated them by, which its memory
/// count needs) and puts those of @p p in their place.
void replace_supernodes(cholmod_factor &L, const Pieces &p, cholmod_common &common)
{
  cholmod_free(L.nsuper + 1, sizeof(int), L.super, &common);
  cholmod_free(L.nsuper + 1, sizeof(int), L.pi, &common);
  cholmod_free(L.nsuper + 1, sizeof(int), L.px, &common);
  cholmod_free(L.ssize, sizeof(int), L.s, &common);
  L.super = p.super;
  L.pi = p.pi;
  L.px = p.px;
  L.s = p.rows;
  L.nsuper = p.n_super;
  L.ssize = p.n_rows;
  L.xsize = p.n_numbers;
}
} // namespace

SupernodeWorkspace supernode_workspace(const cholmod_factor &L)
{
  return workspace_of(L.n, L.nsuper, static_cast<const int *>(L.super), static_cast<const int *>(L.pi),
                      static_cast<const int *>(L.s));
}

SupernodeSplit cap_supernode_width(cholmod_factor &L, const std::size_t max_width, cholmod_common &common)
{
  SupernodeSplit split{L.nsuper, L.nsuper, L.xsize, L.xsize};
  if (!L.is_super || max_width == 0) return split;
  if (L.itype != CHOLMOD_INT || L.xtype != CHOLMOD_PATTERN || L.dtype != CHOLMOD_DOUBLE)
    throw std::invalid_argument("cap_supernode_width: a symbolic factor with int indices is needed");
  Pieces pieces = count_pieces(L, max_width);
  if (pieces.n_super == L.nsuper) return split;
  fill_pieces(L, max_width, pieces, common);
  SupernodeWorkspace w;
  try
    {
      w = workspace_of(L.n, pieces.n_super, pieces.super, pieces.pi, pieces.rows);
    }
  catch (const std::bad_alloc &)
    {
      free_pieces(pieces, common);
      throw;
    }
  replace_supernodes(L, pieces, common);
  L.maxcsize = w.max_update;
  L.maxesize = w.max_rows_below;
  split.supernodes_after = L.nsuper;
  split.numbers_after = L.xsize;
  return split;
}
} // namespace flextrack::reduction
