// The LiDAR's pose in the world from the detected markers of a map (paper Sec. IV), made robust to
// a wrong id, a false positive or a moved marker: markers that disagree with the others are
// dropped.
#pragma once

#include <optional>
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
  // The marker's fitted plane (plane lift), `lidar` lying on it. Its centre, axes and offset and
  // slope variances summarise the plane's inlier points (their centroid, the principal axes of
  // their scatter, and the residual noise over the count and over the spread along each axis),
  // which is all the point-to-plane refinement needs: O(1) per marker, not O(points).
  std::optional<Plane> plane;
  // RMS distance of `lidar` from the best square of the mapped size (0 when not fitted): how far
  // the marker disagrees with its own shape (e.g. corners a ring apart on a coarse spinning LiDAR),
  // which no pose can remove and the map is not to blame for.
  double shape_rms_m = 0;
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
  // Markers whose plane points refined the pose (LidarPoseOptions::refine), and those whose plane
  // disagreed with the corners and was left out (their corners still count).
  std::vector<std::string> planes_used, planes_rejected;
};

enum class PoseRefine {
  kNone,    // the Kabsch pose of the agreeing markers' corners
  kPoints,  // then Gauss-Newton on the corners' rays and the marker-plane points
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
  // base + per_metre * (its distance) + its shape_rms_m: corner errors grow with range, and a
  // marker whose corners are not quite square cannot fit any pose better than its own square.
  double max_marker_residual_m = 0.03;
  double max_marker_residual_per_metre = 0.003;
  // After Kabsch and the robust step: refine with each marker's plane points (refine_lidar_pose).
  PoseRefine refine = PoseRefine::kNone;
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

struct PoseRefinement {
  bool ok = false;  // false: nothing to refine with, or the normal matrix was singular
  Isometry3 T_world_lidar = Isometry3::Identity();
  Mat6 covariance = Mat6::Zero();  // inverse of the Gauss-Newton normal matrix
  std::vector<std::string> planes_used, planes_rejected;
  double chi2 = 0;  // whitened cost at the optimum
  int dof = 0;      // residuals minus 6
};

// Refines T_world_lidar (from `start`, e.g. the Kabsch pose, whose covariance is
// `start_covariance`) by Gauss-Newton on two independent kinds of evidence per marker:
// - its corners' rays: each corner's residual projected along its ray onto the marker's plane
//   (the detection's in-plane error; the plane's error moves a lifted corner along its ray), with
//   the in-plane part of its covariance. Markers without a plane use the full 3-D residual.
// - its plane's points against the map's plane through its corners: the offset at the points'
//   centroid and the two slopes, each over its variance (the moment form of the sum of squared
//   point-to-plane distances, the points' own noise as the fit measured it).
// A plane whose own chi-square (3 dof) exceeds the 99.9 % bound, or that pulls the pose further
// from `start` than `start_covariance` allows (6 dof, 99.9 %; a singular covariance gives no such
// gate), is left out, worst first; with no plane left, nothing is refined (ok = false): the
// corners alone are what `start` already used. The covariance is scaled by the chi-square over
// its degrees of freedom when that exceeds 1.
PoseRefinement refine_lidar_pose(const std::vector<MarkerCorrespondence>& markers,
                                 const Isometry3& start, const Mat6& start_covariance);

}  // namespace iilfm
