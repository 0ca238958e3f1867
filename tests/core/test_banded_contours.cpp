// Contours traced on the rows where an image changes are those of the whole image.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>
#include <string>

#include "../../src/banded_contours.hpp"

namespace iilfm {
namespace {

using Contours = std::vector<std::vector<cv::Point>>;

// A scene like a spinning LiDAR's detector image: uniform rows above and below (of either value,
// in layers), between them blobs, rings, specks touching diagonally, blobs on the left and right
// edges and on the band's first and last rows, and whole uniform rows.
cv::Mat scene(std::mt19937& rng, int rows, int cols, std::uint8_t low, std::uint8_t high) {
  std::uniform_int_distribution<int> coin(0, 1), row_of(0, rows - 1), col_of(0, cols - 1),
      size(1, 12);
  const auto value = [&] { return coin(rng) ? high : low; };
  cv::Mat image(rows, cols, CV_8U, cv::Scalar(value()));
  const int top = row_of(rng), bottom = std::max(top, row_of(rng));
  image.rowRange(0, top).setTo(value());
  image.rowRange(0, top / 2).setTo(value());
  image.rowRange(bottom, rows).setTo(value());
  image.rowRange(std::min(rows, bottom + (rows - bottom) / 2), rows).setTo(value());
  const int shapes = std::uniform_int_distribution<int>(0, 12)(rng);
  for (int k = 0; k < shapes; ++k) {
    const cv::Point at(col_of(rng), std::uniform_int_distribution<int>(top, bottom)(rng));
    const cv::Size extent(size(rng), size(rng) / 2 + 1);
    const cv::Scalar v(value());
    switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
      case 0:
        cv::rectangle(image, cv::Rect(at, extent), v, cv::FILLED);
        break;
      case 1:  // a ring, so holes and nesting occur
        cv::rectangle(image, cv::Rect(at, extent + extent), v, 1);
        break;
      case 2:
        cv::ellipse(image, at, extent, 0, 0, 360, v, cv::FILLED);
        break;
      case 3:  // specks that touch only at corners
        for (int d = 0; d < 4; ++d)
          if (at.y + d < rows && at.x + d < cols) image.at<std::uint8_t>(at.y + d, at.x + d) = v[0];
        break;
      case 4:  // a blob on the left or right edge
        cv::rectangle(
            image, cv::Rect(coin(rng) ? 0 : cols - extent.width, at.y, extent.width, extent.height),
            v, cv::FILLED);
        break;
      default:  // a whole row
        image.row(at.y).setTo(v);
    }
  }
  return image;
}

Contours narrower_of_whole_image(const cv::Mat& image, int mode, int method) {
  Contours all, out;
  cv::findContours(image, all, mode, method);
  for (const auto& contour : all)
    if (cv::boundingRect(contour).width < image.cols) out.push_back(contour);
  return out;
}

bool uniform_row(const cv::Mat& image, int r) {
  double lo, hi;
  cv::minMaxLoc(image.row(r), &lo, &hi);
  return lo == hi;
}

TEST(BandedContours, AreTheContoursOfTheWholeImageInTheirOrder) {
  std::mt19937 rng(29);
  const std::pair<int, int> modes[] = {{cv::RETR_LIST, cv::CHAIN_APPROX_SIMPLE},
                                       {cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE},
                                       {cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE}};
  const cv::Size sizes[] = {{90, 60}, {40, 120}, {7, 9}, {1, 30}, {30, 1}, {2, 2}};
  int banded = 0, compared = 0;
  for (int trial = 0; trial < 1200; ++trial) {
    const cv::Size size = sizes[trial % 6];
    const cv::Mat image = scene(rng, size.height, size.width, 0, 255);
    const cv::Rect band = detail::changing_band(image);
    // Outside the band every row is uniform, and two uniform rows pad it where it stops short
    // of the image's edge.
    const int first = band.empty() ? image.rows : band.y, end = band.y + band.height;
    for (int r = 0; r < image.rows; ++r) {
      const bool outside = r < first || r >= end;
      const bool padding = (first > 0 && r < first + 2) || (end < image.rows && r >= end - 2);
      if (outside || padding) {
        ASSERT_TRUE(uniform_row(image, r)) << "trial " << trial << ", row " << r;
      }
    }
    if (!band.empty() && band.height < image.rows) ++banded;
    for (const auto& [mode, method] : modes) {
      Contours traced;
      detail::contours_narrower_than_image(image, mode, method, traced);
      const Contours expected = narrower_of_whole_image(image, mode, method);
      ASSERT_EQ(traced, expected) << "trial " << trial << ", mode " << mode;
      compared += static_cast<int>(expected.size());
    }
  }
  EXPECT_GT(banded, 350);     // a third of the scenes have uniform rows to skip
  EXPECT_GT(compared, 2500);  // and contours to compare
}

TEST(BandedContours, AGrayImageThresholdedInItsBandGivesTheDarkBlobs) {
  // As dark_quads (ring_decoding.cpp) uses it: the band found on gray values, dark pixels
  // thresholded inside it; rows uniform in gray are uniform when thresholded.
  std::mt19937 rng(31);
  for (int trial = 0; trial < 200; ++trial) {
    const cv::Mat gray = scene(rng, 70, 90, 40, 200);
    gray.row(trial % 70).setTo(100 + trial % 50);  // a uniform row of another, dark level
    cv::Mat dark, band_dark;
    cv::compare(gray, 128, dark, cv::CMP_LT);
    const Contours expected =
        narrower_of_whole_image(dark, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
    const cv::Rect band = detail::changing_band(gray);
    Contours traced;
    if (!band.empty()) {
      cv::compare(gray(band), 128, band_dark, cv::CMP_LT);
      detail::contours_in_band(band_dark, band, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, traced);
    }
    ASSERT_EQ(traced, expected) << "trial " << trial;
  }
}

TEST(BandedContours, AUniformImageHasNoBand) {
  EXPECT_TRUE(detail::changing_band(cv::Mat(20, 30, CV_8U, cv::Scalar(255))).empty());
  cv::Mat stripes(20, 30, CV_8U, cv::Scalar(0));
  stripes.rowRange(5, 9).setTo(255);  // rows differ, but each is uniform
  EXPECT_TRUE(detail::changing_band(stripes).empty());
  stripes.at<std::uint8_t>(12, 3) = 255;
  EXPECT_EQ(detail::changing_band(stripes), cv::Rect(0, 10, 30, 5));
}

}  // namespace
}  // namespace iilfm
