// Minimum and maximum kept in L independent lanes and combined at the end: a loop that feeds
// lane j from every L-th element has no dependence between neighbouring elements, so GCC
// vectorises it, and a minimum or maximum is the same in any order.
#pragma once

#include <algorithm>
#include <cstddef>

namespace iilfm::detail {

template <typename T, std::size_t L>
struct LaneRange {
  T lo[L], hi[L];

  LaneRange(T lo_start, T hi_start) {
    std::fill(lo, lo + L, lo_start);
    std::fill(hi, hi + L, hi_start);
  }
  // Takes `v` into lane j when `take` (a select, not a branch).
  void add(std::size_t j, T v, bool take = true) {
    lo[j] = take && v < lo[j] ? v : lo[j];
    hi[j] = take && v > hi[j] ? v : hi[j];
  }
  T min() const { return *std::min_element(lo, lo + L); }
  T max() const { return *std::max_element(hi, hi + L); }
};

}  // namespace iilfm::detail
