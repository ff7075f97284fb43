// The program's operator new: malloc, with the large allocations on 2 MiB pages
// (base/large_pages.h says why). Trilinos' matrices, sparsity patterns and std::vector all
// allocate through it; CHOLMOD's factor is advised in reduction/sparse_factorization.cc.
//
// Only the two basic forms are replaced: the standard library's array, nothrow and sized
// forms call them, and its operator delete (free) matches malloc. Under AddressSanitizer the
// library's own operators stay, so that it can still match each delete to its new.
#include <base/large_pages.h>

#include <new>

#if !defined(__SANITIZE_ADDRESS__)
namespace
{
void *allocate(std::size_t bytes)
{
  if (bytes == 0) bytes = 1;
  for (;;)
    {
      if (void *pointer = flextrack::base::malloc_on_large_pages(bytes)) return pointer;
      // As the standard asks: let the installed new-handler free memory, or throw.
      std::new_handler handler = std::get_new_handler();
      if (!handler) throw std::bad_alloc();
      handler();
    }
}
} // namespace

void *operator new(std::size_t bytes) { return allocate(bytes); }
void *operator new[](std::size_t bytes) { return allocate(bytes); }
#endif
