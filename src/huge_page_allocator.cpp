#include "iilfm/huge_page_allocator.hpp"

#include <cstdlib>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace iilfm::detail {

namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;

std::size_t rounded_up(std::size_t bytes) {
  return (bytes + kHugePage - 1) / kHugePage * kHugePage;
}
}  // namespace

void* allocate_huge_page_backed(std::size_t bytes) {
  if (bytes < kHugePage) return ::operator new(bytes);
  void* p = std::aligned_alloc(kHugePage, rounded_up(bytes));
  if (!p) throw std::bad_alloc();
#ifdef __linux__
  // Advice only: without transparent huge pages (or with them off) the pages stay 4 KB.
  (void)madvise(p, rounded_up(bytes), MADV_HUGEPAGE);
#endif
  return p;
}

void free_huge_page_backed(void* p, std::size_t bytes) noexcept {
  if (!p) return;
  if (bytes < kHugePage) {
    ::operator delete(p);
  } else {
    std::free(p);
  }
}

}  // namespace iilfm::detail
