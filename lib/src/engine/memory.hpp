// Allocation of the engine's large arrays: aligned to cache lines and, for arrays of several
// megabytes on Linux, backed by transparent huge pages (2 MB). The event loop reads the discs,
// the cells and the heap at random places; with 4 KB pages a system of 10^5 discs or more spans
// more pages than the TLB holds, and every miss costs a page walk.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace billiard {

template <class T>
struct BigArrayAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;
  static constexpr std::size_t kLarge = std::size_t{4} << 20;  // from this size on: huge pages
  BigArrayAllocator() = default;
  template <class U>
  BigArrayAllocator(const BigArrayAllocator<U>&) {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= kLarge) {
      const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
      void* p = std::aligned_alloc(kHugePage, rounded);
      if (p == nullptr) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
      madvise(p, rounded, MADV_HUGEPAGE);  // a hint: ignored where huge pages are off
#endif
      return static_cast<T*>(p);
    }
    return static_cast<T*>(::operator new(bytes, std::align_val_t(64)));
  }
  void deallocate(T* p, std::size_t n) {
    if (n * sizeof(T) >= kLarge) {
      std::free(p);
    } else {
      ::operator delete(p, std::align_val_t(64));
    }
  }
  template <class U>
  bool operator==(const BigArrayAllocator<U>&) const { return true; }
  template <class U>
  bool operator!=(const BigArrayAllocator<U>&) const { return false; }
};

template <class T>
using BigVector = std::vector<T, BigArrayAllocator<T>>;

// Asks the CPU to start loading the cache line that holds `p` (a hint: no fault, no wait). GCC 12
// deletes __builtin_prefetch from a loop that does nothing else: the engine's prefetch of the
// next event's neighbours, a loop over cell records, compiled to an empty function at -O3 and to
// nothing at -O2 (seen in the disassembly). On x86 with GCC or Clang the instruction
// is therefore written as volatile inline assembly, which the compiler must keep.
inline void prefetch_line(const void* p) {
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
  asm volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#else
  __builtin_prefetch(p);
#endif
}

}  // namespace billiard
