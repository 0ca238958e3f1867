// Branch-free float approximations for the projection's hot loop, written so the compiler can
// vectorise them (libm's atan2 costs tens of ns a call, which alone would blow the time budget
// at 600k points).
#pragma once

#include <cmath>

namespace iilfm::detail {

// atan2 with a maximum error of 1.7e-6 rad (0.0001 deg, 1/500 of a 0.05 deg pixel): an odd
// polynomial for atan on [0, 1], least-squares fitted with minimax weighting, then the octant
// reflections atan(t) = pi/2 - atan(1/t), pi - angle for x < 0 and the sign of y.
inline float fast_atan2(float y, float x) {
  const float ax = std::fabs(x), ay = std::fabs(y);
  const float hi = ax > ay ? ax : ay, lo = ax > ay ? ay : ax;
  // Dividing by at least a tiny number instead of branching on hi == 0 (then lo == 0 and t == 0)
  // keeps the function branch-free, so loops calling it vectorise.
  const float t = lo / (hi > 1e-30f ? hi : 1e-30f);
  const float s = t * t;
  float r = -1.1719134575e-02f;
  r = r * s + 5.2647349498e-02f;
  r = r * s - 1.1642648167e-01f;
  r = r * s + 1.9354037701e-01f;
  r = r * s - 3.3262282836e-01f;
  r = r * s + 9.9997721914e-01f;
  r *= t;
  r = ay > ax ? 1.57079632679f - r : r;
  r = x < 0.0f ? 3.14159265359f - r : r;
  return y < 0.0f ? -r : r;
}

}  // namespace iilfm::detail
