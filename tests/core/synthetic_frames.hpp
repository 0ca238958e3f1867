// Synthetic LiDAR frames for tests that need many frames fast, without the simulator.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "iilfm/types.hpp"

namespace iilfm::testing {

// A Mid-40-like frame: directions inside the 38.4 deg cone, a wall at 2-6 m, random intensities.
inline PointCloud livox_like_frame(std::uint32_t seed, std::size_t points) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> angle(-0.33f, 0.33f), range(2.0f, 6.0f),
      intensity(0.f, 150.f);
  PointCloud cloud;
  while (cloud.size() < points) {
    const float a = angle(rng), e = angle(rng);
    if (a * a + e * e > 0.33f * 0.33f) continue;
    const float r = range(rng);
    cloud.push_back(r * std::cos(e) * std::cos(a), r * std::cos(e) * std::sin(a), r * std::sin(e),
                    intensity(rng));
  }
  return cloud;
}

}  // namespace iilfm::testing
