// Scoring one frame: match detections to the true markers in the image, then compare corners,
// marker poses and the LiDAR pose with the truth.
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "iilfm/eval/case.hpp"

namespace iilfm::eval {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

double rotation_angle_deg(const Mat3& estimated, const Mat3& truth) {
  return Eigen::AngleAxisd(estimated.transpose() * truth).angle() * kRadToDeg;
}

// A true marker as the image sees it: where its centre projects and how far its corners reach.
// Column offsets wrap on a full-circle image, so a marker across the seam keeps its small size.
struct MarkerInImage {
  Vec2 centre;
  double radius = 0;
};

Vec2 image_offset(const ImageGeometry& g, const Vec2& from, const Vec2& to) {
  Vec2 d = to - from;
  if (g.full_circle()) {
    const double turn = g.columns_per_turn();
    d.x() -= turn * std::round(d.x() / turn);
  }
  return d;
}

MarkerInImage in_image(const ImageGeometry& g, const sim::MarkerTruth& m) {
  MarkerInImage out;
  out.centre = g.pixel_of_point(m.T_lidar_marker.translation());
  for (const Vec3& corner : m.corners_lidar) {
    out.radius = std::max(out.radius, image_offset(g, out.centre, g.pixel_of_point(corner)).norm());
  }
  return out;
}

// The error of `estimated` in the covariance's convention (pose_covariance.hpp), the predicted
// RMS position (m) and rotation (deg) errors, and the normalised error squared.
struct Claimed {
  double position_sigma = 0, rotation_sigma_deg = 0, nees = 0;
};

// The truth turned about its own z to agree with `estimated` about it: for a marker whose turn
// is unknowable only the face's tilt is an error.
Mat3 turned_like(const Mat3& truth, const Mat3& estimated) {
  const Vec3 x = truth.transpose() * estimated.col(0);
  return truth * Eigen::AngleAxisd(std::atan2(x.y(), x.x()), Vec3::UnitZ()).toRotationMatrix();
}

Claimed claimed(const Isometry3& estimated, const Isometry3& truth, const Mat6& C,
                bool turn_known = true) {
  Eigen::Matrix<double, 6, 1> e;
  const Eigen::AngleAxisd turn(estimated.linear().transpose() * truth.linear());
  e.head<3>() = turn.angle() * turn.axis();
  e.tail<3>() = truth.translation() - estimated.translation();
  Claimed out;
  out.position_sigma = std::sqrt(std::max(0.0, C.bottomRightCorner<3, 3>().trace()));
  const int rotation_axes = turn_known ? 3 : 2;  // without the turn: the tilt's two axes
  out.rotation_sigma_deg =
      std::sqrt(std::max(0.0, C.topLeftCorner(rotation_axes, rotation_axes).trace())) * kRadToDeg;
  const Eigen::LDLT<Mat6> ldlt(C);
  out.nees = ldlt.info() == Eigen::Success ? e.dot(ldlt.solve(e)) : 0;
  return out;
}

Vec2 centroid(const std::vector<Vec2>& points) {
  Vec2 sum = Vec2::Zero();
  for (const Vec2& p : points) sum += p;
  return points.empty() ? sum : sum / static_cast<double>(points.size());
}

}  // namespace

CaseScore score_frame(const FrameResult& result, const sim::GroundTruth& truth) {
  CaseScore s;
  s.time_ms = result.times_ms.total();
  std::vector<MarkerInImage> footprints;
  for (const sim::MarkerTruth& m : truth.markers) {
    footprints.push_back(in_image(result.image.geometry, m));
    s.visible += m.visible ? 1 : 0;
  }
  std::vector<bool> found(truth.markers.size(), false);
  double corner_sum = 0, marker_position_sum = 0, marker_rotation_sum = 0;
  double size_error_sum = 0;
  int sized = 0;
  double marker_position_sigma_sum = 0, marker_rotation_sigma_sum = 0, marker_nees_sum = 0;

  for (const MarkerResult& detected : result.markers) {
    const Vec2 centre = centroid(detected.detection.corners_px);
    // The true marker whose image area holds the detection's centre (the nearest such one).
    int on_marker = -1;
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < truth.markers.size(); ++i) {
      const double d = image_offset(result.image.geometry, footprints[i].centre, centre).norm();
      if (d <= footprints[i].radius && d < nearest) {
        on_marker = int(i);
        nearest = d;
      }
    }
    if (on_marker < 0) {
      ++s.false_positives;
      continue;
    }
    const sim::MarkerTruth& m = truth.markers[on_marker];
    if (detected.detection.family != m.family || detected.detection.id != m.id) {
      ++s.wrong_ids;
      continue;
    }
    if (found[on_marker]) {  // the same marker twice
      ++s.false_positives;
      continue;
    }
    found[on_marker] = true;
    s.detected += m.visible ? 1 : 0;
    for (std::size_t k = 0; k < detected.corners.size() && k < 4; ++k) {
      if (!detected.corners[k].valid()) continue;
      const double error = (detected.corners[k].point - m.corners_lidar[k]).norm();
      corner_sum += error;
      s.corner_error_max = std::max(s.corner_error_max, error);
      ++s.corners;
    }
    if (detected.corners.size() == 4 &&
        std::all_of(detected.corners.begin(), detected.corners.end(),
                    [](const LiftedCorner& c) { return c.valid(); })) {
      double measured = 0, truth_size = 0;
      for (std::size_t k = 0; k < 4; ++k) {
        const auto corner = [&](std::size_t i) {
          return detected.lifted_points.size() == 4 ? detected.lifted_points[i]
                                                    : detected.corners[i].point;
        };
        measured += (corner((k + 1) % 4) - corner(k)).norm() / 4;
        truth_size += (m.corners_lidar[(k + 1) % 4] - m.corners_lidar[k]).norm() / 4;
      }
      size_error_sum += measured - truth_size;
      ++sized;
    }
    if (detected.T_lidar_marker) {
      marker_position_sum +=
          (detected.T_lidar_marker->translation() - m.T_lidar_marker.translation()).norm();
      Isometry3 true_pose = m.T_lidar_marker;
      if (!detected.turn_known)
        true_pose.linear() = turned_like(true_pose.linear(), detected.T_lidar_marker->linear());
      marker_rotation_sum +=
          rotation_angle_deg(detected.T_lidar_marker->linear(), true_pose.linear());
      const Claimed c = claimed(*detected.T_lidar_marker, true_pose,
                                detected.T_lidar_marker_covariance, detected.turn_known);
      marker_position_sigma_sum += c.position_sigma;
      marker_rotation_sigma_sum += c.rotation_sigma_deg;
      marker_nees_sum += c.nees;
      ++s.marker_poses;
    }
  }
  if (s.corners > 0) s.corner_error_mean = corner_sum / s.corners;
  if (sized > 0) s.size_error_mean = size_error_sum / sized;
  if (s.marker_poses > 0) {
    s.marker_position_error_mean = marker_position_sum / s.marker_poses;
    s.marker_rotation_error_mean_deg = marker_rotation_sum / s.marker_poses;
    s.marker_position_sigma_mean = marker_position_sigma_sum / s.marker_poses;
    s.marker_rotation_sigma_mean_deg = marker_rotation_sigma_sum / s.marker_poses;
    s.marker_nees_mean = marker_nees_sum / s.marker_poses;
  }
  if (result.pose) {
    s.pose = true;
    const Isometry3& estimated = result.pose->T_world_lidar;
    s.position_error = (estimated.translation() - truth.T_world_lidar.translation()).norm();
    s.rotation_error_deg = rotation_angle_deg(estimated.linear(), truth.T_world_lidar.linear());
    const Claimed c = claimed(estimated, truth.T_world_lidar, result.pose->covariance);
    s.position_sigma = c.position_sigma;
    s.rotation_sigma_deg = c.rotation_sigma_deg;
    s.pose_nees = c.nees;
  }
  return s;
}

}  // namespace iilfm::eval
