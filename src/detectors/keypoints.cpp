// Keypoints of a detection in the marker frame and in the image.
#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "iilfm/detector.hpp"
#include "iilfm/pose.hpp"

namespace iilfm {

std::vector<Vec3> marker_frame_keypoints(const Detection& detection, double size) {
  std::vector<Vec3> points;
  if (detection.keypoints_marker.empty()) {
    const auto corners = marker_frame_corners(size);
    points.assign(corners.begin(), corners.end());
    points.resize(std::min(points.size(), detection.corners_px.size()));
    return points;
  }
  for (const Vec2& k : detection.keypoints_marker)
    points.emplace_back(k.x() * size, k.y() * size, 0);
  return points;
}

std::vector<Vec2> keypoint_outline(const Detection& detection) {
  if (!detection.outline_px.empty()) return detection.outline_px;
  if (detection.keypoints_marker.empty()) return detection.corners_px;
  std::vector<cv::Point2f> points, hull;
  for (const Vec2& p : detection.corners_px)
    points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  if (points.size() < 3) return detection.corners_px;
  cv::convexHull(points, hull);
  std::vector<Vec2> outline;
  for (const cv::Point2f& p : hull) outline.emplace_back(p.x, p.y);
  return outline;
}

}  // namespace iilfm
