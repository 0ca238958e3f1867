// Markers across the azimuth seam of a full-circle image (a 360-degree LiDAR's image starts and
// ends directly behind the sensor, so a marker there is cut in two and no detector decodes it).
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "iilfm/detector.hpp"
#include "iilfm/projection.hpp"

namespace iilfm {

// The strip across a full-circle image's azimuth seam: the image's last `half` columns, then its
// first `half` from `start` (the first column that continues the last one: the image may hold one
// column twice, +-180 degrees both present, or, for a turn of a fractional number of columns,
// overlap by a part).
struct SeamStrip {
  int width = 0;  // the image's
  int start = 0;
  int half = 0;
  double turn = 0;  // columns per turn

  // The strip for `geometry` (of images `geometry.width` wide), or nullopt unless it covers a full
  // turn.
  static std::optional<SeamStrip> of(const ImageGeometry& geometry);

  // `image`'s strip (`image` is `width` columns wide), into `strip`; empty for an empty one.
  void cut(const cv::Mat& image, cv::Mat& strip) const;
  // The seam in strip coordinates (pixel centres at integers).
  double seam() const { return half - 0.5; }
  // The image's continuous column of strip column x: the left half is the image's end, the right
  // half its start one turn on (column c points where column c + turn does), past the last column.
  double image_u(double x) const { return x < seam() ? width - half + x : x - half + start + turn; }
  // The same, but the right half at its own columns.
  double own_u(double x) const { return x < seam() ? width - half + x : x - half + start; }

  // Where a marker whose keypoints are `points` (strip coordinates) lies, and those keypoints
  // moved to the image's columns accordingly:
  enum class Place {
    kAcross,  // on both sides of the seam: moved by image_u, past the last column
    // wholly on one side but near the seam (within half its width and a few pixels), where the
    // image's edge cuts its white margin or a detector's neighbourhood (a detector reads about a
    // quarter of the width beyond the border and thresholds over a few pixels more), so that the
    // image itself may miss it: moved by own_u
    kNear,
    kAway,  // farther: left as they are (the image holds it whole)
  };
  Place place(const std::vector<Vec2*>& points) const;
};

// Runs the detectors on a strip made of the images' last and first columns side by side (an
// eighth of a turn from each side) and appends the markers that straddle the seam, their
// keypoints in `geometry`'s continuous coordinates: past the last column where the marker
// continues (u >= width), so the quad stays whole. A marker wholly on one side but near the seam
// (its white margin cut by the image's edge) is appended in the image's own columns unless it
// overlaps one of `out`'s detections (the image's own, found before). Only the strip's regions
// around the seam are searched (DetectorImages::crossing_column). Does nothing unless `geometry`
// covers a full turn.
void detect_across_seam(const DetectorImages& images, const ImageGeometry& geometry,
                        const std::vector<std::unique_ptr<MarkerDetector>>& detectors,
                        std::vector<Detection>& out);

}  // namespace iilfm
