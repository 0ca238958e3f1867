#include "banded_contours.hpp"

#include <algorithm>
#include <cstring>
#include <opencv2/imgproc.hpp>

namespace iilfm::detail {

namespace {

bool row_changes(const cv::Mat& image, int r) {
  const std::uint8_t* row = image.ptr<std::uint8_t>(r);
  // Each pixel against its right neighbour, through memcmp (vectorised in libc).
  return image.cols > 1 && std::memcmp(row, row + 1, static_cast<std::size_t>(image.cols - 1));
}

}  // namespace

cv::Rect changing_band(const cv::Mat& image) {
  CV_Assert(image.type() == CV_8UC1);
  int first = 0;
  while (first < image.rows && !row_changes(image, first)) ++first;
  if (first == image.rows) return {};
  int last = image.rows - 1;
  while (!row_changes(image, last)) --last;
  constexpr int kMargin = 2;  // a border pixel one row out, and the neighbours it is checked by
  const int top = std::max(0, first - kMargin);
  const int end = std::min(image.rows, last + 1 + kMargin);
  return {0, top, image.cols, end - top};
}

void contours_narrower_than_image(const cv::Mat& image, int mode, int method,
                                  std::vector<std::vector<cv::Point>>& contours) {
  contours.clear();
  const cv::Rect band = changing_band(image);
  if (!band.empty()) contours_in_band(image(band), band, mode, method, contours);
}

void contours_in_band(const cv::Mat& band_pixels, const cv::Rect& band, int mode, int method,
                      std::vector<std::vector<cv::Point>>& contours) {
  CV_Assert(band_pixels.size() == band.size());
  // findContours pads its input with zeros itself (BORDER_ISOLATED), so a band traces as an image
  // of its own; the offset puts its points in the image's coordinates.
  cv::findContours(band_pixels, contours, mode, method, band.tl());
  // A contour that reaches a uniform row spans the width there, in the band as in the image (where
  // it may run on further): neither version is kept.
  contours.erase(std::remove_if(contours.begin(), contours.end(),
                                [&](const std::vector<cv::Point>& contour) {
                                  return cv::boundingRect(contour).width >= band.width;
                                }),
                 contours.end());
}

}  // namespace iilfm::detail
