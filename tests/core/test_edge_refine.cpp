// Edge-aware corners on a synthetic blurred marker: a global threshold nearer black than the middle
// shrinks the detected square; moving the sides to the marker's own mid level undoes it.
#include <gtest/gtest.h>

#include <algorithm>

#include "iilfm/edge_refine.hpp"

namespace iilfm {
namespace {

constexpr double kBlack = 10, kWhite = 120;

// Share of a box footprint `width` px wide, centred at x, that lies inside [lo, hi].
double covered(double x, double lo, double hi, double width) {
  const double a = std::max(lo, x - width / 2), b = std::min(hi, x + width / 2);
  return std::max(0.0, b - a) / width;
}

// A black square with edges at lo and hi in both directions, white around it, seen through a
// box footprint `width` px wide (separable), every pixel observed.
ProjectedImage blurred_square(double lo, double hi, double width, int size = 120) {
  ProjectedImage image;
  image.geometry.width = image.geometry.height = size;
  image.geometry.res_h = image.geometry.res_v = 0.001;
  image.intensity = cv::Mat(size, size, CV_32F);
  image.mask = cv::Mat(size, size, CV_8U, cv::Scalar(255));
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c)
      image.intensity.at<float>(r, c) = static_cast<float>(
          kWhite - (kWhite - kBlack) * covered(c, lo, hi, width) * covered(r, lo, hi, width));
  return image;
}

std::vector<Vec2> square(double lo, double hi) {
  return {Vec2(lo, lo), Vec2(hi, lo), Vec2(hi, hi), Vec2(lo, hi)};
}

TEST(EdgeRefine, UndoesTheShrinkOfAThresholdNearBlack) {
  const double width = 5;  // footprint in pixels
  const ProjectedImage image = blurred_square(30, 90, width);
  // Threshold 40: a side is found where 8/11 of the footprint is black, 1.14 px inside the edge.
  const double inset = (kWhite - 40) / (kWhite - kBlack) * width - width / 2;
  ASSERT_NEAR(inset, 1.136, 1e-3);
  const EdgeRefinement r =
      refine_edges_to_mid_level(square(30 + inset, 90 - inset), image, /*border_cells=*/8);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.black, kBlack, 1e-6);
  EXPECT_NEAR(r.white, kWhite, 1e-6);
  EXPECT_NEAR(r.mean_shift_px, inset, 0.02);
  const std::vector<Vec2> truth = square(30, 90);
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_LT((r.corners_px[k] - truth[k]).norm(), 0.03) << "corner " << k;
}

TEST(EdgeRefine, LeavesCorrectSidesWhereTheyAre) {
  const ProjectedImage image = blurred_square(30, 90, 3);
  const EdgeRefinement r = refine_edges_to_mid_level(square(30, 90), image, 8);
  ASSERT_TRUE(r.ok);
  for (std::size_t k = 0; k < 4; ++k)
    EXPECT_LT((r.corners_px[k] - square(30, 90)[k]).norm(), 0.03) << "corner " << k;
}

TEST(EdgeRefine, KeepsCoarseOrFlatMarkersAsDetected) {
  // 24 px over 8 cells: 3 px per cell, too coarse for a profile.
  const ProjectedImage coarse = blurred_square(30, 54, 1);
  const EdgeRefinement r = refine_edges_to_mid_level(square(30.5, 53.5), coarse, 8);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.corners_px, square(30.5, 53.5));
  // No contrast (an all-white image): no levels, no move.
  ProjectedImage flat = blurred_square(200, 201, 1);
  EXPECT_FALSE(refine_edges_to_mid_level(square(30, 90), flat, 8).ok);
  // Unobserved image: nothing to sample.
  flat.mask.setTo(0);
  EXPECT_FALSE(refine_edges_to_mid_level(square(30, 90), flat, 8).ok);
}

}  // namespace
}  // namespace iilfm
