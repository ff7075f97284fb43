#include <reduction/supernode_width.h>

#include <algorithm>
#include <new>
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

/// The largest update matrix C (rows x columns of one supernode's contribution to one
/// ancestor) and the most rows below a diagonal block: CHOLMOD's workspaces are sized by these.
/// A descendant's rows below its diagonal block fall into its ancestors in runs; the run for
/// ancestor s gives C = (rows from the run on) x (rows in the run).
/// @p supernode_of: workspace of L.n ints.
void update_workspace_sizes(cholmod_factor &L, std::vector<int> &supernode_of)
{
  const auto *super = static_cast<const int *>(L.super), *pi = static_cast<const int *>(L.pi);
  const auto *rows = static_cast<const int *>(L.s);
  for (std::size_t k = 0; k < L.nsuper; ++k) std::fill(supernode_of.begin() + super[k], supernode_of.begin() + super[k + 1], k);
  std::size_t max_c = 1, max_e = 1;
  for (std::size_t d = 0; d < L.nsuper; ++d)
    {
      const std::size_t end = pi[d + 1];
      std::size_t run = pi[d] + (super[d + 1] - super[d]);
      max_e = std::max(max_e, end - run);
      while (run < end)
        {
          const int s = supernode_of[rows[run]];
          std::size_t next = run;
          while (next < end && supernode_of[rows[next]] == s) ++next;
          max_c = std::max(max_c, (end - run) * (next - run));
          run = next;
        }
    }
  L.maxcsize = max_c;
  L.maxesize = max_e;
}
} // namespace

SupernodeSplit cap_supernode_width(cholmod_factor &L, const std::size_t max_width, cholmod_common &common)
{
  SupernodeSplit split{L.nsuper, L.nsuper, L.xsize, L.xsize};
  if (!L.is_super || L.xtype != CHOLMOD_PATTERN || max_width == 0) return split;
  const auto *super = static_cast<const int *>(L.super), *pi = static_cast<const int *>(L.pi);
  const auto *rows = static_cast<const int *>(L.s);
  auto pieces = [&](const std::size_t k) {
    const std::size_t width = super[k + 1] - super[k];
    return (width + max_width - 1) / max_width;
  };
  // Calls use(k, first, end): the columns [first, end) of each piece of supernode k.
  auto for_each_piece = [&](auto &&use) {
    for (std::size_t k = 0; k < L.nsuper; ++k)
      {
        const std::size_t n_pieces = pieces(k), width = super[k + 1] - super[k];
        std::size_t first = super[k];
        for (std::size_t q = 0; q < n_pieces; ++q)
          {
            const std::size_t end = first + width / n_pieces + (q < width % n_pieces ? 1 : 0);
            use(k, first, end);
            first = end;
          }
      }
  };
  std::size_t n_super = 0, n_rows = 0, n_numbers = 0;
  for_each_piece([&](std::size_t k, std::size_t first, std::size_t end) {
    const std::size_t piece_rows = (pi[k + 1] - pi[k]) - (first - super[k]);
    ++n_super;
    n_rows += piece_rows;
    n_numbers += piece_rows * (end - first);
  });
  if (n_super == L.nsuper) return split;

  std::vector<int> supernode_of(L.n);

  int *new_super = cholmod_ints(n_super + 1, common);
  int *new_pi = nullptr, *new_px = nullptr, *new_rows = nullptr;
  try
    {
      new_pi = cholmod_ints(n_super + 1, common);
      new_px = cholmod_ints(n_super + 1, common);
      new_rows = cholmod_ints(n_rows, common);
    }
  catch (const std::bad_alloc &)
    {
      for (int *p : {new_super, new_pi, new_px})
        if (p) cholmod_free(n_super + 1, sizeof(int), p, &common);
      throw;
    }
  std::size_t piece = 0, row = 0, number = 0;
  for_each_piece([&](std::size_t k, std::size_t first, std::size_t end) {
    // The piece's rows: its own columns, then the rest of the supernode's and those below.
    const int *from = rows + pi[k] + (first - super[k]), *to = rows + pi[k + 1];
    new_super[piece] = first;
    new_pi[piece] = row;
    new_px[piece] = number;
    std::copy(from, to, new_rows + row);
    row += to - from;
    number += (to - from) * (end - first);
    ++piece;
  });
  new_super[n_super] = L.n;
  new_pi[n_super] = row;
  new_px[n_super] = number;

  cholmod_free(L.nsuper + 1, sizeof(int), L.super, &common);
  cholmod_free(L.nsuper + 1, sizeof(int), L.pi, &common);
  cholmod_free(L.nsuper + 1, sizeof(int), L.px, &common);
  cholmod_free(L.ssize, sizeof(int), L.s, &common);
  L.super = new_super;
  L.pi = new_pi;
  L.px = new_px;
  L.s = new_rows;
  L.nsuper = n_super;
  L.ssize = n_rows;
  L.xsize = n_numbers;
  update_workspace_sizes(L, supernode_of);
  split.supernodes_after = n_super;
  split.numbers_after = n_numbers;
  return split;
}
} // namespace flextrack::reduction
