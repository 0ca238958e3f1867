#include "iilfm/marker_coverage.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace iilfm {

namespace {

struct OutlineTally {
  std::size_t inside = 0, observed = 0, points = 0;
};

OutlineTally tally_outline(const Detection& detection, const ProjectedImage& image) {
  OutlineTally t;
  const std::vector<Vec2> outline = keypoint_outline(detection);
  if (outline.size() < 3 || image.mask.empty()) return t;
  const bool counted = image.count.size() == image.mask.size();
  double u_min = outline[0].x(), u_max = u_min, v_min = outline[0].y(), v_max = v_min;
  double area = 0;  // twice the signed area: its sign says which way the outline turns
  for (std::size_t k = 0; k < outline.size(); ++k) {
    const Vec2& a = outline[k];
    const Vec2& b = outline[(k + 1) % outline.size()];
    u_min = std::min(u_min, a.x());
    u_max = std::max(u_max, a.x());
    v_min = std::min(v_min, a.y());
    v_max = std::max(v_max, a.y());
    area += a.x() * b.y() - a.y() * b.x();
  }
  const double turn = area >= 0 ? 1.0 : -1.0;
  const int c0 = std::max(0, static_cast<int>(std::ceil(u_min)));
  const int c1 = std::min(image.mask.cols - 1, static_cast<int>(std::floor(u_max)));
  const int r0 = std::max(0, static_cast<int>(std::ceil(v_min)));
  const int r1 = std::min(image.mask.rows - 1, static_cast<int>(std::floor(v_max)));
  // Inside a convex outline: on the inner side of every edge.
  const auto inside = [&](int r, int c) {
    for (std::size_t k = 0; k < outline.size(); ++k) {
      const Vec2& a = outline[k];
      const Vec2& b = outline[(k + 1) % outline.size()];
      const double cross = (b.x() - a.x()) * (r - a.y()) - (b.y() - a.y()) * (c - a.x());
      if (!(cross * turn >= 0)) return false;
    }
    return true;
  };
  for (int r = r0; r <= r1; ++r) {
    // Each edge's test is monotone along a row (so are the rounded operations that compute it),
    // so a row's pixels inside are one run: found from its ends, then tallied without tests.
    int lo = c0, hi = c1;
    while (lo <= hi && !inside(r, lo)) ++lo;
    while (hi >= lo && !inside(r, hi)) --hi;
    const std::uint8_t* m = image.mask.ptr<std::uint8_t>(r);
    const std::int32_t* n = counted ? image.count.ptr<std::int32_t>(r) : nullptr;
    for (int c = lo; c <= hi; ++c) {
      ++t.inside;
      t.observed += m[c] ? 1 : 0;
      t.points += n ? static_cast<std::size_t>(std::max(0, n[c])) : (m[c] ? 1 : 0);
    }
  }
  return t;
}

}  // namespace

double marker_coverage(const Detection& detection, const ProjectedImage& image) {
  const OutlineTally t = tally_outline(detection, image);
  return t.inside ? static_cast<double>(t.observed) / static_cast<double>(t.inside) : 0.0;
}

double marker_points_per_pixel(const Detection& detection, const ProjectedImage& image) {
  const OutlineTally t = tally_outline(detection, image);
  return t.inside ? static_cast<double>(t.points) / static_cast<double>(t.inside) : 0.0;
}

}  // namespace iilfm
