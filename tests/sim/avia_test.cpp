// Livox Avia: the elliptical rosette fills 70.4 x 77.2 deg at 240k points/s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "iilfm/sim/sim.hpp"
#include "plain_wall.hpp"

namespace iilfm::sim {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

TEST(Avia, DataSheetFigures) {
  const SensorModel s = sensor_model("avia");
  EXPECT_EQ(s.pattern, ScanPattern::kRosette);
  EXPECT_DOUBLE_EQ(s.fov_deg, 70.4);
  EXPECT_DOUBLE_EQ(s.fov_v_deg, 77.2);
  EXPECT_DOUBLE_EQ(s.points_per_second, 240000);
  EXPECT_DOUBLE_EQ(s.range_sigma_m, 0.02);
  EXPECT_EQ(points_per_frame(s), 24000);
}

TEST(Avia, PatternSpansTheFieldOfViewAtTheDataSheetRate) {
  // A wall 5 m ahead, 20 m square: wider than the 38.6 deg half-angle reaches (4 m).
  const Scene wall = testing::plain_wall(5, 20, 50);
  SimOptions o;
  o.frames = 2;
  o.range_sigma_m = 0;
  const SimResult r = simulate(wall, avia(), o);
  ASSERT_EQ(r.cloud.size(), 48000u);  // every beam hits the wall
  double max_azimuth = 0, max_elevation = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Vec3 p = r.cloud.point(i);
    max_azimuth = std::max(max_azimuth, std::abs(std::atan2(p.y(), p.x())) * kRadToDeg);
    max_elevation = std::max(max_elevation, std::abs(std::atan2(p.z(), p.x())) * kRadToDeg);
    // Inside the ellipse of half-angles 35.2 x 38.6 deg (angle from the axis split along y, z).
    const double rho = std::acos(p.x() / p.norm());
    const double lateral = std::hypot(p.y(), p.z());
    if (lateral > 0) {
      const double u = rho * p.y() / lateral / (35.2 / kRadToDeg);
      const double v = rho * p.z() / lateral / (38.6 / kRadToDeg);
      ASSERT_LE(u * u + v * v, 1 + 1e-6) << i;
    }
  }
  // The petal tips reach the rim: within a few tenths of a degree of the half-angles.
  EXPECT_NEAR(max_azimuth, 35.2, 0.3);
  EXPECT_NEAR(max_elevation, 38.6, 0.3);
  // Point k fires at k / 240 000 s.
  EXPECT_DOUBLE_EQ(r.cloud.time[0], 0);
  EXPECT_NEAR(r.cloud.time[24000], 0.1, 1e-12);
  EXPECT_NEAR(r.cloud.time.back() - r.cloud.time.front(), 47999.0 / 240000, 1e-12);
}

TEST(Avia, GroundTruthUsesTheEllipticalFieldOfView) {
  // A marker 38 deg to the side is outside the 35.2 deg horizontal half-angle, one 37 deg up
  // is inside the 38.6 deg vertical half-angle; the circular Mid-40 cone sees neither.
  const double d = 3;
  Scene scene;
  scene.markers = {wall_marker("apriltag:tag36h11", 0, 0.1, d, d * std::tan(38 / kRadToDeg), 0),
                   wall_marker("apriltag:tag36h11", 1, 0.1, d, 0, d * std::tan(37 / kRadToDeg))};
  const GroundTruth avia_truth = ground_truth(scene, avia(), SimOptions{});
  EXPECT_FALSE(avia_truth.markers[0].visible);
  EXPECT_TRUE(avia_truth.markers[1].visible);
  const GroundTruth mid40_truth = ground_truth(scene, mid40(), SimOptions{});
  EXPECT_FALSE(mid40_truth.markers[1].visible);
}

}  // namespace
}  // namespace iilfm::sim
