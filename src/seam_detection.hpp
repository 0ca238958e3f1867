// Markers across the azimuth seam of a full-circle image (a 360-degree LiDAR's image starts and
// ends directly behind the sensor, so a marker there is cut in two and no detector decodes it).
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "iilfm/detector.hpp"
#include "iilfm/projection.hpp"

namespace iilfm {

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
