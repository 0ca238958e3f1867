// Point-in-polygon for the convex outlines of detections (corners in either orientation).
#pragma once

#include <vector>

#include "iilfm/types.hpp"

namespace iilfm::detail {

// True when `p` lies inside or on the convex polygon `poly`; false for fewer than 3 corners.
inline bool inside_convex(const Vec2& p, const std::vector<Vec2>& poly) {
  if (poly.size() < 3) return false;
  int sign = 0;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Vec2 e = poly[(k + 1) % poly.size()] - poly[k], q = p - poly[k];
    const double cross = e.x() * q.y() - e.y() * q.x();
    const int s = cross > 0 ? 1 : cross < 0 ? -1 : 0;
    if (s != 0 && sign != 0 && s != sign) return false;
    if (s != 0) sign = s;
  }
  return true;
}

}  // namespace iilfm::detail
