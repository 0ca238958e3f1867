#include "seam_detection.hpp"

#include <algorithm>
#include <cmath>

namespace iilfm {

void detect_across_seam(const DetectorImages& images, const ImageGeometry& geometry,
                        const std::vector<std::unique_ptr<MarkerDetector>>& detectors,
                        std::vector<Detection>& out) {
  const cv::Mat& image = images.image;
  if (!geometry.full_circle() || image.cols != geometry.width || image.cols < 16) return;
  const int width = image.cols;
  const double turn = geometry.columns_per_turn();
  // The first column that continues the last one: the image may hold one column twice (+-180
  // degrees both present) or, for a turn of a fractional number of columns, overlap by a part.
  const int start = std::clamp(static_cast<int>(std::lround(width - turn)), 0, width / 4);
  const int half = std::max(8, width / 8);
  // Each image's strip (empty for an empty one).
  thread_local DetectorImages strip;
  const auto strip_of = [&](const cv::Mat& from, cv::Mat& to) {
    if (from.empty()) {
      to.release();
    } else {
      cv::hconcat(from.colRange(width - half, width), from.colRange(start, start + half), to);
    }
  };
  strip_of(image, strip.image);
  strip_of(images.gray.size() == image.size() ? images.gray : cv::Mat(), strip.gray);
  strip_of(images.valid.size() == image.size() ? images.valid : cv::Mat(), strip.valid);

  // Strip coordinate x to the image's continuous column: the left half is the image's end, the
  // right half its start one turn on (column c points where column c + turn does).
  const auto image_u = [&](double x) {
    return x < half - 0.5 ? width - half + x : x - half + start + turn;
  };
  std::vector<Detection> found;
  for (const auto& detector : detectors) detector->detect_images(strip, found);
  for (Detection& d : found) {
    // Keypoints and outline (a ring marker has one keypoint, its centre, and an outline).
    std::vector<Vec2*> points;
    for (Vec2& p : d.corners_px) points.push_back(&p);
    for (Vec2& p : d.outline_px) points.push_back(&p);
    const bool left = std::any_of(points.begin(), points.end(),
                                  [&](const Vec2* p) { return p->x() < half - 0.5; });
    const bool right = std::any_of(points.begin(), points.end(),
                                   [&](const Vec2* p) { return p->x() >= half - 0.5; });
    if (!left || !right) continue;  // wholly on one side: the image itself holds it whole
    for (Vec2* p : points) p->x() = image_u(p->x());
    out.push_back(std::move(d));
  }
}

}  // namespace iilfm
