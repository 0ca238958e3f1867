// Marker coverage (include/iilfm/marker_coverage.hpp): the share of a marker's pixels that hold a
// point, on masks whose answer is known.
#include <gtest/gtest.h>

#include "iilfm/marker_coverage.hpp"

namespace iilfm {
namespace {

ProjectedImage image_with_mask(const cv::Mat& mask) {
  ProjectedImage image;
  image.mask = mask;
  image.geometry.width = mask.cols;
  image.geometry.height = mask.rows;
  return image;
}

Detection square(double u0, double v0, double u1, double v1) {
  Detection d;
  d.family = "apriltag:tag36h11";
  d.corners_px = {Vec2(u0, v0), Vec2(u1, v0), Vec2(u1, v1), Vec2(u0, v1)};
  return d;
}

TEST(MarkerCoverage, CountsObservedPixelCentresInsideTheOutline) {
  cv::Mat mask = cv::Mat::zeros(40, 40, CV_8U);
  // Every other column observed.
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; c += 2) mask.at<std::uint8_t>(r, c) = 255;
  const ProjectedImage image = image_with_mask(mask);
  // Columns 10..19 (centres 10, 11, ..., 19 inside [9.5, 19.5]): half observed.
  EXPECT_DOUBLE_EQ(marker_coverage(square(9.5, 9.5, 19.5, 19.5), image), 0.5);
  // Either corner order (the detector's is clockwise on screen).
  Detection reversed = square(9.5, 9.5, 19.5, 19.5);
  std::reverse(reversed.corners_px.begin(), reversed.corners_px.end());
  EXPECT_DOUBLE_EQ(marker_coverage(reversed, image), 0.5);
  mask.setTo(255);
  EXPECT_DOUBLE_EQ(marker_coverage(square(9.5, 9.5, 19.5, 19.5), image), 1.0);
  mask.setTo(0);
  EXPECT_DOUBLE_EQ(marker_coverage(square(9.5, 9.5, 19.5, 19.5), image), 0.0);
}

TEST(MarkerCoverage, ATurnedSquareCountsOnlyItsInside) {
  cv::Mat mask = cv::Mat::zeros(60, 60, CV_8U);
  mask(cv::Rect(0, 0, 60, 30)).setTo(255);  // the upper half observed
  const ProjectedImage image = image_with_mask(mask);
  Detection diamond;
  diamond.family = "apriltag:tag36h11";
  diamond.corners_px = {Vec2(30, 10.2), Vec2(49.8, 30), Vec2(30, 49.8), Vec2(10.2, 30)};
  // Rows 11..29 of the diamond are observed, 30..49 not: a little under half.
  const double coverage = marker_coverage(diamond, image);
  EXPECT_GT(coverage, 0.45);
  EXPECT_LT(coverage, 0.5);
}

TEST(MarkerCoverage, OutsideTheImageOrDegenerateGivesZero) {
  const ProjectedImage image = image_with_mask(cv::Mat(20, 20, CV_8U, cv::Scalar(255)));
  EXPECT_EQ(marker_coverage(square(30, 30, 40, 40), image), 0.0);
  Detection line;
  line.corners_px = {Vec2(1, 1), Vec2(5, 5)};
  EXPECT_EQ(marker_coverage(line, image), 0.0);
}

}  // namespace
}  // namespace iilfm
