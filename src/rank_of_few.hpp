// The k-th smallest of a few values, the selection the ring-sample reader makes hundreds of times
// per candidate square (the median of its black samples and of its white ones, ~100 each).
#pragma once

#include <cstddef>

namespace iilfm::detail {

// The value of rank `k` (0-based: the k-th smallest) among `values[0, n)`, as std::nth_element
// places it; k < n. Up to kFewValues values it counts the values below and equal to a trial value
// (a loop without branches that vectorises, where nth_element's partitioning mispredicts about
// every other comparison), each trial narrowing the range the answer lies in; above, nth_element.
// Reorders `values` only in that case.
constexpr std::size_t kFewValues = 192;
float value_of_rank_among_few(float* values, std::size_t n, std::size_t k);

}  // namespace iilfm::detail
