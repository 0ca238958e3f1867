#include "iilfm/duplicates.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace iilfm {

namespace {

std::vector<cv::Point2f> polygon(const Detection& d) {
  std::vector<cv::Point2f> points;
  for (const Vec2& p : d.corners_px)
    points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  // intersectConvexConvex wants one orientation; reverse clockwise-in-area outlines.
  if (points.size() >= 3 && cv::contourArea(points, true) < 0)
    std::reverse(points.begin(), points.end());
  return points;
}

}  // namespace

double outline_overlap(const Detection& a, const Detection& b) {
  const std::vector<cv::Point2f> pa = polygon(a), pb = polygon(b);
  if (pa.size() < 3 || pb.size() < 3) return 0;
  const double area_a = cv::contourArea(pa), area_b = cv::contourArea(pb);
  if (!(area_a > 0) || !(area_b > 0)) return 0;
  std::vector<cv::Point2f> common;
  const double inter = cv::intersectConvexConvex(pa, pb, common, true);
  if (!(inter > 0)) return 0;
  return inter / (area_a + area_b - inter);
}

std::size_t drop_duplicate_detections(std::vector<Detection>& detections,
                                      const std::function<bool(const Detection&)>& preferred,
                                      double min_overlap) {
  std::vector<bool> dropped(detections.size(), false);
  for (std::size_t i = 0; i < detections.size(); ++i) {
    for (std::size_t j = i + 1; j < detections.size() && !dropped[i]; ++j) {
      if (dropped[j] || detections[i].family == detections[j].family) continue;
      if (outline_overlap(detections[i], detections[j]) < min_overlap) continue;
      // The earlier detection (the family listed first) stays unless only the later is preferred.
      const bool later_wins = preferred && preferred(detections[j]) && !preferred(detections[i]);
      dropped[later_wins ? i : j] = true;
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < detections.size(); ++i) {
    if (dropped[i]) continue;
    if (kept != i) detections[kept] = std::move(detections[i]);
    ++kept;
  }
  const std::size_t removed = detections.size() - kept;
  detections.resize(kept);
  return removed;
}

}  // namespace iilfm
