#include "seam_detection.hpp"

#include <algorithm>
#include <cmath>

#include "iilfm/duplicates.hpp"

namespace iilfm {

namespace {

// A marker wholly on one side of the seam is near it when its keypoints come within this share of
// its width plus this many pixels of it: a detector reads about a quarter of the width beyond the
// border, and thresholds over a few pixels more (search_regions.hpp).
constexpr double kNearSeamShare = 0.5;
constexpr double kNearSeamPx = 8;
// Outlines overlapping this much (intersection over union) are one marker.
constexpr double kSameMarkerOverlap = 0.3;

}  // namespace

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
  strip.crossing_column = half;  // only what crosses the seam is kept below

  // Strip coordinate x to the image's continuous column: the left half is the image's end, the
  // right half its start one turn on (column c points where column c + turn does).
  const auto image_u = [&](double x) {
    return x < half - 0.5 ? width - half + x : x - half + start + turn;
  };
  const std::size_t own = out.size();  // the image's own detections
  std::vector<Detection> found;
  for (const auto& detector : detectors) detector->detect_images(strip, found);
  for (Detection& d : found) {
    // Keypoints and outline (a ring marker has one keypoint, its centre, and an outline).
    std::vector<Vec2*> points;
    for (Vec2& p : d.corners_px) points.push_back(&p);
    for (Vec2& p : d.outline_px) points.push_back(&p);
    if (points.empty()) continue;
    double lo = points[0]->x(), hi = lo;
    for (const Vec2* p : points) {
      lo = std::min(lo, p->x());
      hi = std::max(hi, p->x());
    }
    const double seam = half - 0.5;
    if (lo < seam && hi >= seam) {
      for (Vec2* p : points) p->x() = image_u(p->x());
      out.push_back(std::move(d));
      continue;
    }
    // Wholly on one side but near the seam, where the image's edge cut its white margin or the
    // detector's neighbourhood: the image itself may have missed it (an OS1-64's 40 cm tag at 2 m
    // with its border 0.3 degrees from the seam was found in neither). Kept in the image's own
    // columns, unless the image found it.
    const bool left = hi < seam;
    const double gap = left ? seam - hi : lo - seam;
    if (gap > kNearSeamShare * (hi - lo) + kNearSeamPx) continue;
    for (Vec2* p : points) p->x() = left ? width - half + p->x() : p->x() - half + start;
    const bool known = std::any_of(
        out.begin(), out.begin() + static_cast<std::ptrdiff_t>(own),
        [&](const Detection& o) { return outline_overlap(o, d) >= kSameMarkerOverlap; });
    if (!known) out.push_back(std::move(d));
  }
}

}  // namespace iilfm
