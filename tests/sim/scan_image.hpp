// Test helper: a simulated scan projected as ARCHITECTURE.md prescribes (u = u0 - azimuth/res,
// v = v0 - elevation/res) into an 8-bit intensity image, independently of the pipeline's code.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "iilfm/sim/sim.hpp"

namespace iilfm::sim::testing {

constexpr double kRadToDeg = 180.0 / M_PI;

// A square image of +-half_deg around the x axis.
struct Projection {
  double res_deg, half_deg;
  int size() const { return static_cast<int>(std::lround(2 * half_deg / res_deg)); }
  // Continuous pixel coordinates, pixel centres at i + 0.5 (libapriltag's convention; OpenCV's
  // centres are at i, half a pixel up-left).
  Vec2 pixel(const Vec3& p) const {
    const double azimuth = std::atan2(p.y(), p.x()) * kRadToDeg;
    const double elevation = std::atan2(p.z(), std::hypot(p.x(), p.y())) * kRadToDeg;
    return Vec2((half_deg - azimuth) / res_deg, (half_deg - elevation) / res_deg);
  }
};

// Mean intensity per pixel, scaled to 8 bits; empty pixels take the mean of their neighbours.
inline std::vector<std::uint8_t> intensity_image(const PointCloud& cloud, const Projection& proj) {
  const int n = proj.size();
  std::vector<double> sum(n * n, 0);
  std::vector<int> count(n * n, 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec2 px = proj.pixel(cloud.point(i));
    const int u = static_cast<int>(std::floor(px.x())), v = static_cast<int>(std::floor(px.y()));
    if (u < 0 || u >= n || v < 0 || v >= n) continue;
    sum[v * n + u] += cloud.intensity[i];
    ++count[v * n + u];
  }
  std::vector<std::uint8_t> image(n * n, 128);
  for (int v = 0; v < n; ++v) {
    for (int u = 0; u < n; ++u) {
      double s = 0;
      int c = 0;
      for (int dv = -1; dv <= 1 && count[v * n + u] == 0; ++dv) {
        for (int du = -1; du <= 1; ++du) {
          const int uu = u + du, vv = v + dv;
          if (uu < 0 || uu >= n || vv < 0 || vv >= n) continue;
          s += sum[vv * n + uu];
          c += count[vv * n + uu];
        }
      }
      if (count[v * n + u] > 0) {
        s = sum[v * n + u];
        c = count[v * n + u];
      }
      if (c > 0) image[v * n + u] = static_cast<std::uint8_t>(std::min(255.0, 2.0 * s / c));
    }
  }
  return image;
}

}  // namespace iilfm::sim::testing
