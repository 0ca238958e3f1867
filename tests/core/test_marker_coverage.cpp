// Marker coverage (include/iilfm/marker_coverage.hpp): the share of a marker's pixels that hold a
// point, on masks whose answer is known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

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

// The definition, pixel by pixel: a pixel centre inside when on the inner side of every edge.
std::pair<double, double> coverage_by_definition(const Detection& d, const ProjectedImage& image) {
  const std::vector<Vec2>& q = d.corners_px;
  double area = 0;
  for (std::size_t k = 0; k < q.size(); ++k)
    area += q[k].x() * q[(k + 1) % q.size()].y() - q[k].y() * q[(k + 1) % q.size()].x();
  const double turn = area >= 0 ? 1.0 : -1.0;
  double inside = 0, observed = 0, points = 0;
  for (int r = 0; r < image.mask.rows; ++r)
    for (int c = 0; c < image.mask.cols; ++c) {
      bool in = true;
      for (std::size_t k = 0; k < q.size(); ++k) {
        const Vec2 &a = q[k], &b = q[(k + 1) % q.size()];
        in = in && ((b.x() - a.x()) * (r - a.y()) - (b.y() - a.y()) * (c - a.x())) * turn >= 0;
      }
      if (!in) continue;
      inside += 1;
      observed += image.mask.at<std::uint8_t>(r, c) ? 1 : 0;
      points += image.count.at<std::int32_t>(r, c);
    }
  return {inside ? observed / inside : 0.0, inside ? points / inside : 0.0};
}

TEST(MarkerCoverage, RandomQuadsGiveTheCountsOfTheDefinition) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coordinate(-5, 45), angle(0, 2 * M_PI), size(0.5, 25);
  int nonzero = 0;
  for (int trial = 0; trial < 400; ++trial) {
    cv::Mat mask(40, 40, CV_8U), count(40, 40, CV_32S);
    for (int r = 0; r < 40; ++r)
      for (int c = 0; c < 40; ++c) {
        const int n = static_cast<int>(rng() % 4);
        count.at<std::int32_t>(r, c) = n;
        mask.at<std::uint8_t>(r, c) = n ? 255 : 0;
      }
    ProjectedImage image = image_with_mask(mask);
    image.count = count;
    // A turned, sheared quad (convex), either way round; some with corners on pixel centres.
    const Vec2 centre(coordinate(rng), coordinate(rng));
    const double a = angle(rng), s = size(rng), t = size(rng);
    Detection d;
    d.family = "apriltag:tag36h11";
    for (int k = 0; k < 4; ++k) {
      const double turn = a + k * M_PI / 2 + (k % 2 ? 0.2 : 0.0);
      Vec2 p = centre + (k % 2 ? s : t) * Vec2(std::cos(turn), std::sin(turn));
      if (trial % 3 == 0) p = p.array().round();
      d.corners_px.push_back(p);
    }
    if (trial % 2) std::reverse(d.corners_px.begin(), d.corners_px.end());
    const auto [coverage, per_pixel] = coverage_by_definition(d, image);
    EXPECT_EQ(marker_coverage(d, image), coverage) << trial;
    EXPECT_EQ(marker_points_per_pixel(d, image), per_pixel) << trial;
    nonzero += coverage > 0;
  }
  EXPECT_GT(nonzero, 200);
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
