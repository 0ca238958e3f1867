// Contour tracing limited to the rows where an image changes. A scan's detector image is often
// uniform for whole rows above and below the scene (no returns from the sky, ring rows repeated
// for square pixels: 130 of a ULTRA Puck image's 178 rows), and OpenCV's tracing costs a pass
// over every pixel it is given. A contour in those rows spans the image's width; every other
// contour lies within a row of a row that changes, and its tracing reads one row further.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace iilfm::detail {

// The rows of the 8-bit `image` holding every change between neighbours along a row, widened by
// the two rows each side that tracing reads (clipped to the image), at full width; empty when
// every row is uniform.
cv::Rect changing_band(const cv::Mat& image);

// What cv::findContours(image, contours, mode, method) gives, without the contours whose box
// spans the image's width, in the same order: traced on changing_band(image) alone.
void contours_narrower_than_image(const cv::Mat& image, int mode, int method,
                                  std::vector<std::vector<cv::Point>>& contours);

// The same from the pixels of the band alone: `band_pixels` holds rows `band` of an image as wide,
// where `band` is changing_band of it (or of an image whose uniform rows it keeps uniform, as a
// threshold does). Points in the image's coordinates.
void contours_in_band(const cv::Mat& band_pixels, const cv::Rect& band, int mode, int method,
                      std::vector<std::vector<cv::Point>>& contours);

}  // namespace iilfm::detail
