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

}  // namespace billiard
