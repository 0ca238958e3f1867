// The allocator of the projection's scattered buffers: small blocks from operator new, large ones
// 2 MB aligned (advised for huge pages), both usable through std::vector.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

#include "iilfm/huge_page_allocator.hpp"

namespace iilfm {
namespace {

TEST(HugePageAllocator, LargeBlocksAreAlignedToAHugePageAndHoldTheirValues) {
  constexpr std::size_t kHugePage = std::size_t{2} << 20;
  std::vector<std::uint32_t, detail::HugePageAllocator<std::uint32_t>> large(3 * kHugePage / 4 + 5);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(large.data()) % kHugePage, 0u);
  std::iota(large.begin(), large.end(), 0u);
  EXPECT_EQ(large.back(), large.size() - 1);
  EXPECT_EQ(large[kHugePage / 4], kHugePage / 4);
  // Grown past its capacity: moved to a new block, values kept.
  large.resize(2 * large.size());
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(large.data()) % kHugePage, 0u);
  EXPECT_EQ(large[12345], 12345u);
  EXPECT_EQ(large.back(), 0u);  // new elements value-initialised
}

TEST(HugePageAllocator, SmallBlocksAreOrdinary) {
  std::vector<double, detail::HugePageAllocator<double>> small(100, 1.5);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % alignof(double), 0u);
  EXPECT_EQ(std::accumulate(small.begin(), small.end(), 0.0), 150.0);
  small.clear();
  small.shrink_to_fit();
  EXPECT_EQ(small.capacity(), 0u);
}

}  // namespace
}  // namespace iilfm
