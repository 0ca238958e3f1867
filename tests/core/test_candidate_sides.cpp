// A ring candidate's left and right sides moved to where the rows cross the edge: the binary
// image's sides lie on pixel edges, and the mixed pixel across a printed edge says where it lies.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "../../src/candidate_sides.hpp"

namespace iilfm {
namespace {

constexpr double kBlack = 10, kWhite = 120, kWall = 60;

// A row of pixels one pixel wide each (box footprint): a black square from `left` to `right`
// (columns, pixel centres at integers) on rows 3-8, a one-pixel white quiet zone on each side and
// wall beyond. Rows 2 and 9 hold the quiet zone's white across.
ProjectedImage marker_rows(double left, double right, int width = 40, int height = 12) {
  ProjectedImage image;
  image.geometry.width = width;
  image.geometry.height = height;
  image.geometry.res_h = image.geometry.res_v = 0.001;
  image.intensity = cv::Mat(height, width, CV_32F, cv::Scalar(kWall));
  image.mask = cv::Mat(height, width, CV_8U, cv::Scalar(255));
  const auto share = [](double c, double lo, double hi) {
    return std::max(0.0, std::min(hi, c + 0.5) - std::max(lo, c - 0.5));
  };
  for (int r = 2; r <= 9; ++r) {
    for (int c = 0; c < width; ++c) {
      const double paper = share(c, left - 1.2, right + 1.2);
      const double black = r >= 3 && r <= 8 ? share(c, left, right) : 0;
      image.intensity.at<float>(r, c) =
          static_cast<float>(kWall * (1 - paper) + kWhite * (paper - black) + kBlack * black);
    }
  }
  return image;
}

TEST(CandidateSides, LeftAndRightSidesMoveToTheMixedPixelsEdge) {
  // The binary image cut the square at pixel edges: 12.5 to 22.5, where the print spans 12.5 to
  // 23.1 (pixel 23 is 60 % black, so white in the binary image).
  const ProjectedImage image = marker_rows(12.5, 23.1);
  const std::array<Vec2, 4> quad = {Vec2(22.5, 2.5), Vec2(22.5, 8.5), Vec2(12.5, 8.5),
                                    Vec2(12.5, 2.5)};
  const auto measured = detail::measured_side_columns(quad, image, image.intensity, kBlack, kWhite);
  ASSERT_TRUE(measured);
  EXPECT_NEAR((*measured)[0].x(), 23.1, 0.02);
  EXPECT_NEAR((*measured)[1].x(), 23.1, 0.02);
  EXPECT_NEAR((*measured)[2].x(), 12.5, 0.02);
  EXPECT_NEAR((*measured)[3].x(), 12.5, 0.02);
  for (int k = 0; k < 4; ++k) EXPECT_EQ((*measured)[k].y(), quad[k].y());  // rows stay
}

TEST(CandidateSides, ASideMovesAtMostTheGivenShiftAndNotWithoutAnEdgeInReach) {
  const ProjectedImage image = marker_rows(12.5, 23.1);
  // The right side at 22.0: the rows cross at 23.17 (the box footprint's linear ramp between
  // pixel centres 23 and 24), 1.17 pixels out, so it moves the one pixel allowed.
  const std::array<Vec2, 4> near = {Vec2(22.0, 2.5), Vec2(22.0, 8.5), Vec2(12.5, 8.5),
                                    Vec2(12.5, 2.5)};
  const auto measured =
      detail::measured_side_columns(near, image, image.intensity, kBlack, kWhite, 1.0);
  ASSERT_TRUE(measured);
  EXPECT_NEAR((*measured)[0].x(), 23.0, 1e-9);
  // The right side two and a half pixels inside the print: the pixels searched (a pixel and a
  // half either side) are all black, so no row says where the edge is.
  const std::array<Vec2, 4> inside = {Vec2(20.5, 2.5), Vec2(20.5, 8.5), Vec2(12.5, 8.5),
                                      Vec2(12.5, 2.5)};
  EXPECT_FALSE(detail::measured_side_columns(inside, image, image.intensity, kBlack, kWhite, 1.0));
}

TEST(CandidateSides, NothingWithoutContrastOrWithoutRows) {
  const ProjectedImage image = marker_rows(12.5, 23.1);
  const std::array<Vec2, 4> quad = {Vec2(22.5, 2.5), Vec2(22.5, 8.5), Vec2(12.5, 8.5),
                                    Vec2(12.5, 2.5)};
  // Levels that are not apart.
  EXPECT_FALSE(detail::measured_side_columns(quad, image, image.intensity, kWhite, kBlack));
  // A quad one row tall: under two rows per side.
  const std::array<Vec2, 4> flat = {Vec2(22.5, 4.5), Vec2(22.5, 5.5), Vec2(12.5, 5.5),
                                    Vec2(12.5, 4.5)};
  EXPECT_FALSE(detail::measured_side_columns(flat, image, image.intensity, kBlack, kWhite));
  // A uniform image: no row steps across the mid level.
  ProjectedImage blank = image;
  blank.intensity.setTo(cv::Scalar(kWhite));
  EXPECT_FALSE(detail::measured_side_columns(quad, blank, blank.intensity, kBlack, kWhite));
}

// A quad turned a little, corners in any order: the sides nearer the vertical are the left and
// right ones, and each moves with both its ends; the top and bottom only through those ends.
TEST(CandidateSides, TheLeftAndRightSidesMoveByTheirOwnShifts) {
  const std::array<Vec2, 4> quad = {Vec2(20.4, 8), Vec2(20, 14), Vec2(10, 14.5), Vec2(10.3, 8.2)};
  const std::array<int, 4> facing = detail::side_facings(quad);
  EXPECT_EQ(facing, (std::array<int, 4>{1, 0, -1, 0}));
  const std::array<Vec2, 4> moved = detail::sides_moved(quad, -0.5, 0.25);
  const std::array<Vec2, 4> expected = {Vec2(20.65, 8), Vec2(20.25, 14), Vec2(9.5, 14.5),
                                        Vec2(9.8, 8.2)};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(moved[k].x(), expected[k].x()) << "corner " << k;
    EXPECT_EQ(moved[k].y(), quad[k].y()) << "corner " << k;
  }
  // Starting at the top-left corner gives the same sides, each in its own place.
  const std::array<Vec2, 4> turned = {quad[3], quad[0], quad[1], quad[2]};
  EXPECT_EQ(detail::side_facings(turned), (std::array<int, 4>{0, 1, 0, -1}));
}

// A quad whose left and right sides lean (fitted to a binary outline ragged by a column): they
// are turned about their middles to meet the top and bottom sides square, in angle, with columns
// twice as wide as rows. The top and bottom sides stay on their lines.
TEST(CandidateSides, LeaningLeftAndRightSidesAreSquaredToTheTopAndBottom) {
  // Top from (10, 20) to (17, 20.5), bottom from (11, 34) to (18, 34.5): in angle (x2 on the
  // columns) they run along (14, 0.5); the square's left and right sides run along (-0.5, 14).
  const std::array<Vec2, 4> quad = {Vec2(10, 20), Vec2(17, 20.5), Vec2(18.5, 34.5), Vec2(11, 34)};
  const auto squared = detail::squared_left_right_sides(quad, 2.0, 1.0);
  ASSERT_TRUE(squared);
  const auto angle = [](const Vec2& p) { return Vec2(2 * p.x(), p.y()); };
  const std::array<Vec2, 4>& q = *squared;
  // Each corner on its top or bottom line.
  const auto on_line = [](const Vec2& p, const Vec2& a, const Vec2& b) {
    const Vec2 d = b - a, e = p - a;
    return std::abs(d.x() * e.y() - d.y() * e.x()) / d.norm();
  };
  EXPECT_LT(on_line(q[0], quad[0], quad[1]), 1e-9);
  EXPECT_LT(on_line(q[1], quad[0], quad[1]), 1e-9);
  EXPECT_LT(on_line(q[2], quad[3], quad[2]), 1e-9);
  EXPECT_LT(on_line(q[3], quad[3], quad[2]), 1e-9);
  // Left and right sides at right angles to the top, in angle, through the old sides' middles.
  const Vec2 top = (angle(quad[1]) - angle(quad[0])).normalized();
  for (const auto& [a, b] : {std::pair{1, 2}, std::pair{3, 0}}) {
    const Vec2 side = angle(q[static_cast<std::size_t>(b)]) - angle(q[static_cast<std::size_t>(a)]);
    EXPECT_NEAR(side.normalized().dot(top), 0.0, 0.03) << "side " << a;
    const Vec2 old_middle =
        0.5 * (quad[static_cast<std::size_t>(a)] + quad[static_cast<std::size_t>(b)]);
    EXPECT_LT(on_line(old_middle, q[static_cast<std::size_t>(a)], q[static_cast<std::size_t>(b)]),
              1e-9);
  }
  // The right side leaned 1.5 columns over 14 rows: now its ends lie within a third of that.
  EXPECT_LT(std::abs(q[2].x() - q[1].x()), 0.5);
  // No top and bottom pair: nothing.
  EXPECT_FALSE(
      detail::squared_left_right_sides({Vec2(0, 0), Vec2(1, 0), Vec2(1, 0), Vec2(0, 0)}, 2.0, 1.0));
}

}  // namespace
}  // namespace iilfm
