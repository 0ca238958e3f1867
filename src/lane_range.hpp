// Minimum and maximum kept in L independent lanes and combined at the end: a loop that feeds
// lane j from every L-th element has no dependence between neighbouring elements, so GCC
// vectorises it, and a minimum or maximum is the same in any order.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>

namespace iilfm::detail {

template <typename T, std::size_t L>
struct LaneRange {
  T lo[L], hi[L];

  LaneRange(T lo_start, T hi_start) {
    std::fill(lo, lo + L, lo_start);
    std::fill(hi, hi + L, hi_start);
  }
  // Takes `v` into lane j when `take`. A skipped value becomes an infinity that changes nothing,
  // so every lane is written on every call: written as a conditional store, GCC vectorised it
  // with masked stores and reloads through the stack (store forwarding failed on each, 8x slower).
  // A NaN never wins, as before.
  void add(std::size_t j, T v, bool take = true) {
    constexpr T kInf = std::numeric_limits<T>::infinity();
    const T low = take ? v : kInf, high = take ? v : -kInf;
    lo[j] = low < lo[j] ? low : lo[j];
    hi[j] = high > hi[j] ? high : hi[j];
  }
  T min() const { return *std::min_element(lo, lo + L); }
  T max() const { return *std::max_element(hi, hi + L); }
};

}  // namespace iilfm::detail
