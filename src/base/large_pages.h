// Large arrays on 2 MiB pages (transparent huge pages).
//
// Why: reducing a 1e5-dof body touches about 2 GiB of fresh memory (K, M, their restricted
// copies, the Cholesky factor). On 4 KiB pages that is about 550 000 page faults and as many TLB
// entries; on the virtual machines we measured, each fault costs several microseconds and the
// TLB misses of the memory-bound triangular solves cost more: glibc's own switch for this
// (GLIBC_TUNABLES=glibc.malloc.hugetlb=1, read only when a process starts) took the 1e5-dof
// reduction from 22.3 s to 17.6 s of user time (one run each, 2026-12-02; doc/benchmarks.md).
//
// What: advise_large_pages asks the kernel to back every whole 2 MiB page inside an allocation
// with a huge page on first touch (madvise MADV_HUGEPAGE; honoured when the kernel's THP mode is
// "madvise" or "always", a no-op when it is "never"). Only allocations of at least 4 MiB are
// advised, so that each holds at least one whole huge page and no small object is made to pin
// 2 MiB of memory. malloc_on_large_pages and calloc_on_large_pages are malloc and calloc followed
// by that advice: memory from them is released with free. glibc serves blocks below its mmap
// threshold (up to 32 MiB) from the heap: the advice then stays on that part of the heap after
// the block is freed, and what is allocated there later is on huge pages too, which costs at
// most the rounding to 2 MiB of that region. calloc zeroes heap blocks itself, before the
// advice: those keep 4 KiB pages (blocks it maps fresh are advised before they are touched).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace flextrack::base
{
/// Size of a transparent huge page on x86-64 and of the advised granularity [bytes].
inline constexpr std::size_t large_page_bytes = std::size_t(2) << 20;
/// Allocations from this size on are advised [bytes].
inline constexpr std::size_t large_allocation_bytes = 2 * large_page_bytes;

inline void advise_large_pages(void *pointer, const std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (pointer == nullptr || bytes < large_allocation_bytes) return;
  const auto begin = reinterpret_cast<std::uintptr_t>(pointer);
  const std::uintptr_t first = (begin + large_page_bytes - 1) & ~(std::uintptr_t(large_page_bytes) - 1);
  const std::uintptr_t last = (begin + bytes) & ~(std::uintptr_t(large_page_bytes) - 1);
  // Advice only: where the kernel refuses it (THP off, an old kernel) the pages stay 4 KiB.
  if (last > first) madvise(reinterpret_cast<void *>(first), last - first, MADV_HUGEPAGE);
#else
  (void)pointer;
  (void)bytes;
#endif
}

inline void *malloc_on_large_pages(const std::size_t bytes)
{
  void *pointer = std::malloc(bytes);
  advise_large_pages(pointer, bytes);
  return pointer;
}
inline void *calloc_on_large_pages(const std::size_t count, const std::size_t size)
{
  void *pointer = std::calloc(count, size);
  // A product that overflows has already made calloc fail (nullptr).
  if (pointer) advise_large_pages(pointer, count * size);
  return pointer;
}
} // namespace flextrack::base
