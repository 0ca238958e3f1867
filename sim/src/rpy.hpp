// Internal: roll-pitch-yaw in degrees, extrinsic x-y-z, R = Rz(yaw) Ry(pitch) Rx(roll)
// (docs/pipeline.md), as scene files write orientations.
#pragma once

#include <algorithm>
#include <cmath>

#include "iilfm/types.hpp"

namespace iilfm::sim {

inline Mat3 rotation_from_rpy_deg(const Vec3& rpy) {
  constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
  return (Eigen::AngleAxisd(rpy.z() * kDegToRad, Vec3::UnitZ()) *
          Eigen::AngleAxisd(rpy.y() * kDegToRad, Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy.x() * kDegToRad, Vec3::UnitX()))
      .toRotationMatrix();
}

// Pitch in [-90, 90]; at +-90 the roll is set to 0 and the yaw carries the rest.
inline Vec3 rpy_deg_from_rotation(const Mat3& R) {
  constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  double roll, yaw;
  if (std::abs(R(2, 0)) < 1 - 1e-12) {
    roll = std::atan2(R(2, 1), R(2, 2));
    yaw = std::atan2(R(1, 0), R(0, 0));
  } else {
    roll = 0;
    yaw = std::atan2(-R(0, 1), R(1, 1));
  }
  return Vec3(roll, pitch, yaw) * kRadToDeg;
}

}  // namespace iilfm::sim
