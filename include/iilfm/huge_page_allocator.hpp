// An allocator for the few large buffers read in scattered order (the projection's pixel
// accumulators, the sliding window's per-pixel sums): above 2 MB their memory is asked to be backed
// by transparent huge pages, so that a scattered access does not also miss the TLB (a Mid-40
// image's accumulators span 2300 pages of 4 KB). The kernel may refuse; the memory is then
// ordinary.
#pragma once

#include <cstddef>
#include <new>

namespace iilfm::detail {

// At least `bytes` bytes aligned to alignof(std::max_align_t), or to 2 MB and advised for huge
// pages from 2 MB on; std::bad_alloc when there is no memory.
void* allocate_huge_page_backed(std::size_t bytes);
// Frees what allocate_huge_page_backed(bytes) gave.
void free_huge_page_backed(void* p, std::size_t bytes) noexcept;

template <typename T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_huge_page_backed(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { free_huge_page_backed(p, n * sizeof(T)); }
  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
  template <typename U>
  bool operator!=(const HugePageAllocator<U>&) const noexcept {
    return false;
  }
};

}  // namespace iilfm::detail
