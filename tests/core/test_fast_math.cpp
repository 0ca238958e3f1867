#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../../src/fast_math.hpp"

namespace iilfm {
namespace {

TEST(FastAtan2, StaysWithinTwoMicroradiansEverywhere) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> coordinate(-100, 100);
  double worst = 0;
  for (int i = 0; i < 1'000'000; ++i) {
    const float y = coordinate(rng), x = coordinate(rng);
    worst = std::max(worst, std::abs(detail::fast_atan2(y, x) - std::atan2(double(y), double(x))));
  }
  // Axes, diagonals and the quadrant seams, where the reflections meet.
  for (float a = -M_PI; a <= M_PI; a += M_PI / 8) {
    const float y = std::sin(a), x = std::cos(a);
    worst = std::max(worst, std::abs(detail::fast_atan2(y, x) - std::atan2(double(y), double(x))));
  }
  EXPECT_LT(worst, 2.5e-6);  // 0.00014 deg: 1/350 of the finest preset's pixel (0.05 deg)
  EXPECT_EQ(detail::fast_atan2(0.0f, 0.0f), 0.0f);
  EXPECT_NEAR(detail::fast_atan2(0.0f, -1.0f), M_PI, 1e-6);
  EXPECT_NEAR(detail::fast_atan2(1.0f, 0.0f), M_PI / 2, 1e-6);
  EXPECT_NEAR(detail::fast_atan2(-1.0f, 0.0f), -M_PI / 2, 1e-6);
}

}  // namespace
}  // namespace iilfm
