#include "rank_of_few.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "cpu_clones.hpp"

namespace iilfm::detail {

namespace {

// How many of values[0, n) lie below `x`, and how many equal it.
IILFM_AVX2_CLONES void count_below_and_equal(const float* __restrict values, std::size_t n, float x,
                                             std::uint32_t& below, std::uint32_t& equal) {
  std::uint32_t b = 0, e = 0;
  for (std::size_t j = 0; j < n; ++j) {
    b += values[j] < x ? 1u : 0u;
    e += values[j] == x ? 1u : 0u;
  }
  below = b;
  equal = e;
}

}  // namespace

float value_of_rank_among_few(float* values, std::size_t n, std::size_t k) {
  if (n <= kFewValues) {
    // The value of rank k has at most k values below it and more than k below or equal. Each
    // value tried narrows the open interval (lo, hi) holding it, as a quickselect's pivot does,
    // without moving any value; the next value tried is the first inside the interval. No value
    // qualifies only when one is NaN, which no ordering ranks.
    float lo = 0, hi = 0;
    bool above_lo = false, below_hi = false;  // whether lo, hi bound the interval yet
    for (std::size_t i = 0; i < n; ++i) {
      const float x = values[i];
      if (std::isnan(x) || (above_lo && !(x > lo)) || (below_hi && !(x < hi))) continue;
      std::uint32_t below = 0, equal = 0;
      count_below_and_equal(values, n, x, below, equal);
      if (below > k) {
        hi = x;
        below_hi = true;
      } else if (k >= static_cast<std::size_t>(below) + equal) {
        lo = x;
        above_lo = true;
      } else {
        return x;
      }
    }
  }
  std::nth_element(values, values + k, values + n);
  return values[k];
}

}  // namespace iilfm::detail
