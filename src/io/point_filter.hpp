// The one rule every reader applies to the points it decoded: drop what a driver marks as "no
// return" (all-zero coordinates) and what no later stage can use (non-finite values).
//
// Readers grow the cloud by a block of points, decode straight into the new slots, then filter
// that block in place: each column is written once and no pass runs over the whole cloud again.
#pragma once

#include <cstddef>

#include "iilfm/types.hpp"

namespace iilfm::io {

// Points a reader decodes before filtering them: small enough to stay in cache.
inline constexpr std::size_t kDecodeBlockPoints = 4096;

// Grows each column by n zero-filled points (ring and time only when wanted; intensity stays 0 for
// files without one) and returns the index of the first new point.
std::size_t grow_columns(PointCloud& cloud, std::size_t n, bool with_ring, bool with_time);

// Removes, in place and in order, the points from index `first` on that have a non-finite x, y, z
// or intensity (counted in stats.non_finite) or x = y = z = 0 (stats.zero); adds the kept ones to
// stats.valid_points.
void drop_invalid_points(PointCloud& cloud, std::size_t first, CloudStats& stats);

}  // namespace iilfm::io
