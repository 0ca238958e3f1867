// The LiDAR's pose in the world from the detected markers of a map (paper Sec. IV), made robust to
// a wrong id, a false positive or a moved marker: markers that disagree with the others are
// dropped.
#pragma once

#include <string>
#include <vector>

#include "iilfm/pose_covariance.hpp"
#include "iilfm/types.hpp"

namespace iilfm {

// One detected, mapped marker: its lifted corners and where the map puts them.
struct MarkerCorrespondence {
  std::string key;          // "family/id"
  std::vector<Vec3> world;  // map corners whose lifted counterpart exists
  std::vector<Vec3> lidar;  // the lifted corners, same order
  // Joint covariance of `lidar` (3n x 3n, metres^2); empty when unknown (then the fit's residual
  // stands in for every corner's noise).
  Eigen::MatrixXd lidar_covariance;
};

struct RejectedMarker {
  std::string key;
  double residual_m = 0;  // RMS distance of its corners from where the accepted pose puts them
};

struct LidarPose {
  Isometry3 T_world_lidar = Isometry3::Identity();
  double rms = 0;                         // corner residual after alignment, metres
  std::vector<std::string> markers_used;  // "family/id"
  std::vector<RejectedMarker> markers_rejected;
  std::size_t corners_used = 0;
  // 6x6 over (rx, ry, rz, x, y, z) of T_world_lidar (pose_covariance.hpp): right-perturbation
  // rotation in the LiDAR frame (rad), LiDAR position in the world (m).
  Mat6 covariance = Mat6::Zero();
};

struct LidarPoseOptions {
  // Fewer lifted, mapped corners in the accepted markers: no pose (4: one marker seen whole).
  std::size_t min_corners = 4;
  // A pose whose corner RMS residual exceeds this is not reported (metres).
  double max_rms_m = 0.05;
  // Weigh each corner by the inverse of its variance (the trace of its covariance block) in the
  // Kabsch fit; off: every corner alike.
  bool weight_corners = false;
  // A marker is consistent with a pose when its corners' RMS residual is under
  // base + per_metre * (its distance): corner errors grow with range.
  double max_marker_residual_m = 0.03;
  double max_marker_residual_per_metre = 0.003;
};

struct LidarPoseResult {
  bool ok = false;
  LidarPose pose;
  std::string failure;  // why there is no pose
  // No pose although mapped markers were found: refused for too few corners, a residual over the
  // bound, markers disagreeing, or collinear corners (`failure` says which).
  bool rejected = false;
};

// Kabsch on all consistent markers' corners. With three or more markers, each marker's own pose is
// a hypothesis and the one most markers agree with wins (a RANSAC over markers, exhaustive since
// maps are small); the others are reported as rejected. With one or two markers nothing can be
// outvoted, and a pose whose markers disagree beyond the tolerance is refused.
LidarPoseResult estimate_lidar_pose(const std::vector<MarkerCorrespondence>& markers,
                                    const LidarPoseOptions& options = {});

}  // namespace iilfm
