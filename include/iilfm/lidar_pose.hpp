// The LiDAR's pose in the world from the detected markers of a map (paper Sec. IV), made robust to
// a wrong id, a false positive or a moved marker: markers that disagree with the others are
// dropped.
#pragma once

#include <string>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm {

// One detected, mapped marker: its lifted corners and where the map puts them.
struct MarkerCorrespondence {
  std::string key;          // "family/id"
  std::vector<Vec3> world;  // map corners whose lifted counterpart exists
  std::vector<Vec3> lidar;  // the lifted corners, same order
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
};

struct LidarPoseOptions {
  std::size_t min_corners = 4;  // fewer lifted, mapped corners: no pose
  // A marker is consistent with a pose when its corners' RMS residual is under
  // base + per_metre * (its distance): corner errors grow with range.
  double max_marker_residual_m = 0.03;
  double max_marker_residual_per_metre = 0.003;
};

struct LidarPoseResult {
  bool ok = false;
  LidarPose pose;
  std::string failure;  // why there is no pose
};

// Kabsch on all consistent markers' corners. With three or more markers, each marker's own pose is
// a hypothesis and the one most markers agree with wins (a RANSAC over markers, exhaustive since
// maps are small); the others are reported as rejected. With one or two markers nothing can be
// outvoted, and a pose whose markers disagree beyond the tolerance is refused.
LidarPoseResult estimate_lidar_pose(const std::vector<MarkerCorrespondence>& markers,
                                    const LidarPoseOptions& options = {});

}  // namespace iilfm
