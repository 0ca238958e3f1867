// Rigid alignment of corresponding 3-D point sets (paper Sec. IV) and pose conversions.
#pragma once

#include <array>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm {

struct RigidFit {
  Isometry3 T = Isometry3::Identity();  // maps source points onto target points
  double rms = 0;                       // root mean square residual, metres
  bool ok = false;                      // false: fewer than 3 points or all (nearly) collinear
};

// Closed-form least-squares rotation and translation (Kabsch / Umeyama without scale) with
// T * source[i] ~ target[i]. Always a proper rotation: a reflection is never returned, even
// when the point sets are mirror images of each other. `weights` (empty: all 1) weigh each pair's
// squared residual (weighted Procrustes); `rms` stays the unweighted residual.
RigidFit fit_rigid(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                   const std::vector<double>& weights = {});

// Corners of a square marker of edge `size` in its own frame (centre origin, x right, y up,
// z out of the face): top-left, top-right, bottom-right, bottom-left.
std::array<Vec3, 4> marker_frame_corners(double size);

// Roll-pitch-yaw (extrinsic x-y-z, i.e. R = Rz(yaw) Ry(pitch) Rx(roll)) in degrees.
Vec3 rpy_deg(const Mat3& R);
Mat3 rotation_from_rpy_deg(const Vec3& rpy);

}  // namespace iilfm
