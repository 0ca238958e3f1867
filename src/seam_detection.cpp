#include "seam_detection.hpp"

#include <algorithm>
#include <cmath>

#include "iilfm/duplicates.hpp"

namespace iilfm {

namespace {

// Outlines overlapping this much (intersection over union) are one marker.
constexpr double kSameMarkerOverlap = 0.3;

// `d` moved `du` columns along the image.
Detection shifted(const Detection& d, double du) {
  Detection moved = d;
  for (Vec2& p : moved.corners_px) p.x() += du;
  return moved;
}

}  // namespace

SeamStrip::Place SeamStrip::place(const std::vector<Vec2*>& points) const {
  if (points.empty()) return Place::kAway;
  double lo = points[0]->x(), hi = lo;
  for (const Vec2* p : points) {
    lo = std::min(lo, p->x());
    hi = std::max(hi, p->x());
  }
  const double at = seam();
  if (lo < at && hi >= at) {
    for (Vec2* p : points) p->x() = image_u(p->x());
    return Place::kAcross;
  }
  const double gap = hi < at ? at - hi : lo - at;
  if (gap > 0.5 * (hi - lo) + 8) return Place::kAway;
  for (Vec2* p : points) p->x() = own_u(p->x());
  return Place::kNear;
}

std::optional<SeamStrip> SeamStrip::of(const ImageGeometry& geometry) {
  if (!geometry.full_circle() || geometry.width < 16) return std::nullopt;
  SeamStrip strip;
  strip.width = geometry.width;
  strip.turn = geometry.columns_per_turn();
  strip.start =
      std::clamp(static_cast<int>(std::lround(strip.width - strip.turn)), 0, strip.width / 4);
  strip.half = std::max(8, strip.width / 8);
  return strip;
}

void SeamStrip::cut(const cv::Mat& image, cv::Mat& strip) const {
  if (image.empty()) {
    strip.release();
    return;
  }
  CV_Assert(image.cols == width);
  cv::hconcat(image.colRange(width - half, width), image.colRange(start, start + half), strip);
}

void detect_across_seam(const DetectorImages& images, const ImageGeometry& geometry,
                        const std::vector<std::unique_ptr<MarkerDetector>>& detectors,
                        std::vector<Detection>& out) {
  const cv::Mat& image = images.image;
  const std::optional<SeamStrip> seam_strip = SeamStrip::of(geometry);
  if (!seam_strip || image.cols != geometry.width) return;
  const SeamStrip& cut = *seam_strip;
  thread_local DetectorImages strip;
  cut.cut(image, strip.image);
  cut.cut(images.gray.size() == image.size() ? images.gray : cv::Mat(), strip.gray);
  cut.cut(images.valid.size() == image.size() ? images.valid : cv::Mat(), strip.valid);
  strip.crossing_column = cut.half;  // only what crosses the seam is kept below

  const std::size_t own = out.size();  // the image's own detections
  std::vector<bool> drop(own, false);  // those found whole across the seam
  std::vector<Detection> found;
  for (const auto& detector : detectors) detector->detect_images(strip, found);
  for (Detection& d : found) {
    // Keypoints and outline (a ring marker has one keypoint, its centre, and an outline).
    std::vector<Vec2*> points;
    for (Vec2& p : d.corners_px) points.push_back(&p);
    for (Vec2& p : d.outline_px) points.push_back(&p);
    const SeamStrip::Place place = cut.place(points);
    if (place == SeamStrip::Place::kAway) continue;
    if (place == SeamStrip::Place::kAcross) {
      // The image may also hold a cut-off reading of it (libapriltag decoded a 1 m tag on a
      // VLP-16 from the columns after the seam, its quad short of the border): the whole one wins.
      for (std::size_t i = 0; i < own; ++i)
        if (!drop[i] && out[i].family == d.family && out[i].id == d.id &&
            outline_overlap(shifted(out[i], cut.turn), d) >= kSameMarkerOverlap)
          drop[i] = true;
      out.push_back(std::move(d));
      continue;
    }
    // Near the seam on one side: kept in the image's own columns, unless the image found it (an
    // OS1-64's 40 cm tag at 2 m with its border 0.3 degrees from the seam was found in neither).
    const bool known = std::any_of(
        out.begin(), out.begin() + static_cast<std::ptrdiff_t>(own),
        [&](const Detection& o) { return outline_overlap(o, d) >= kSameMarkerOverlap; });
    if (!known) out.push_back(std::move(d));
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (i < own && drop[i]) continue;
    if (kept != i) out[kept] = std::move(out[i]);
    ++kept;
  }
  out.resize(kept);
}

}  // namespace iilfm
