#include <gtest/gtest.h>

#include <random>

#include "iilfm/pose.hpp"
#include "iilfm/square_shape.hpp"

namespace iilfm {
namespace {

Isometry3 some_pose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Isometry3 T = Isometry3::Identity();
  T.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
  T.translation() = Vec3(u(rng), u(rng), u(rng)) * 10;
  return T;
}

std::array<Vec3, 4> placed(const Isometry3& T, std::array<Vec3, 4> corners) {
  for (Vec3& c : corners) c = T * c;
  return corners;
}

TEST(NearestSquare, ASquareAnywhereIsItselfWithItsEdge) {
  std::mt19937 rng(3);
  for (const double size : {0.05, 0.172, 1.0}) {
    const Isometry3 T = some_pose(rng);
    const SquareShape s = nearest_square(placed(T, marker_frame_corners(size)));
    EXPECT_NEAR(s.side_m, size, 1e-12 * size);
    EXPECT_LT(s.rms_m, 1e-12);
    EXPECT_LT((s.centre - T.translation()).norm(), 1e-12);
  }
}

// A 0.3 x 0.2 rectangle: the nearest square has the mean edge, 0.25, and each corner lies
// (0.025, 0.025) from its corner, sqrt(2) * 0.025 away.
TEST(NearestSquare, ARectangleIsItsMeanSquareWithTheCornersOffByTheDifference) {
  std::mt19937 rng(5);
  const std::array<Vec3, 4> rectangle = {Vec3(-0.15, 0.1, 0), Vec3(0.15, 0.1, 0),
                                         Vec3(0.15, -0.1, 0), Vec3(-0.15, -0.1, 0)};
  const SquareShape s = nearest_square(placed(some_pose(rng), rectangle));
  EXPECT_NEAR(s.side_m, 0.25, 1e-12);
  EXPECT_NEAR(s.rms_m, std::sqrt(2.0) * 0.025, 1e-12);
}

// Corners that go round the square in mirrored order are the square seen from behind; corners
// that cross over (a bow-tie) are no square at all.
TEST(NearestSquare, CornerOrderCountsButNotTheSideItIsSeenFrom) {
  std::array<Vec3, 4> corners = marker_frame_corners(0.2);
  std::swap(corners[1], corners[3]);
  EXPECT_LT(nearest_square(corners).rms_m, 1e-12);
  corners = marker_frame_corners(0.2);
  std::swap(corners[1], corners[2]);
  const SquareShape bow_tie = nearest_square(corners);
  EXPECT_GT(bow_tie.rms_m, bow_tie.side_m);  // measured 1.22 edges
}

}  // namespace
}  // namespace iilfm
