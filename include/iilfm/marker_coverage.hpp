// How much of a detected marker the LiDAR actually measured: the share of the projected image's
// pixels inside the marker's outline that hold a point (before any hole filling). A non-repetitive
// scanner's coverage grows with integration time; a low figure says the detection leaned on
// filled pixels.
#pragma once

#include "iilfm/detector.hpp"
#include "iilfm/projection.hpp"

namespace iilfm {

// Fraction in [0, 1] of the pixels whose centres lie inside the detection's outline (its corners,
// or a board's keypoint hull; projected-image coordinates) that are observed; 0 when no pixel
// centre lies inside.
double marker_coverage(const Detection& detection, const ProjectedImage& image);

// The LiDAR points per pixel inside the same outline (every pixel counted, observed or not); 0
// when no pixel centre lies inside.
double marker_points_per_pixel(const Detection& detection, const ProjectedImage& image);

}  // namespace iilfm
