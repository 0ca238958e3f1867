// Square pixels for the detector. A spinning LiDAR's rows are much coarser than its columns
// (VLP-16: 2 deg vs 0.2 deg), so a square marker is squashed ten to one in the projected image.
// The detector gets the image resampled to rows as fine as the columns; its corners map back to
// the projected image exactly, because both images are exact functions of azimuth and elevation.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "iilfm/projection.hpp"

namespace iilfm {

// Rows are resampled when they (or the gaps between some rings) are more than this many times
// coarser than the columns.
inline constexpr double kSquarePixelRatio = 1.5;

// True when `g` should be resampled for the detector.
bool needs_square_pixels(const ImageGeometry& g);

// The detector's geometry for `g`: same columns, uniform rows spaced like the columns (or like
// the finest ring spacing, when that is finer), spanning the same elevations.
ImageGeometry square_pixel_geometry(const ImageGeometry& g);

// Resamples the rows of a CV_32F image and its CV_8U validity mask from geometry `from` to `to`
// (same columns): each row takes the nearer of the two source rows around its elevation (or the
// valid one of them). Nearest, not linear: a black/white edge between two rings then lies exactly
// half-way between them whatever the threshold, where interpolation would move it towards the
// darker ring by the threshold's distance from mid-grey (measured on the ULTRA Puck ccw10m case:
// LiDAR position error 3.5x smaller than with linear rows). With `repeats_row_above`, also
// says which output rows are copies of the one above (1) and which are not (0): most of them on a
// spinning LiDAR, whose rings lie several square pixels apart. With `repeats_row_above` and
// `copy_repeated_values` false, the repeated rows of `out_image` are left unwritten (a caller that
// reads only the rows that do not repeat saves copying them; the mask is written whole).
void resample_rows(const cv::Mat& image, const cv::Mat& valid, const ImageGeometry& from,
                   const ImageGeometry& to, cv::Mat& out_image, cv::Mat& out_valid,
                   std::vector<std::uint8_t>* repeats_row_above = nullptr,
                   bool copy_repeated_values = true);

// The continuous coordinates in `to` of the direction at `px` in `from`.
inline Vec2 map_pixel(const Vec2& px, const ImageGeometry& from, const ImageGeometry& to) {
  return to.pixel_of_angles(from.azimuth_of_u(px.x()), from.elevation_of_v(px.y()));
}

}  // namespace iilfm
