// Livox Horizon and HAP (elliptical rosettes) and Mid-360 (a 360 deg band): data sheet figures,
// the field each pattern fills, and how the band fills in as frames are integrated.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "iilfm/sim/sim.hpp"
#include "plain_wall.hpp"

namespace iilfm::sim {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

double azimuth_deg(const Vec3& p) { return std::atan2(p.y(), p.x()) * kRadToDeg; }
double elevation_deg(const Vec3& p) { return std::asin(p.z() / p.norm()) * kRadToDeg; }

TEST(LivoxWide, DataSheetFigures) {
  const SensorModel horizon = sensor_model("horizon");
  EXPECT_EQ(horizon.pattern, ScanPattern::kRosette);
  EXPECT_DOUBLE_EQ(horizon.fov_deg, 81.7);
  EXPECT_DOUBLE_EQ(horizon.fov_v_deg, 25.1);
  EXPECT_EQ(points_per_frame(horizon), 24000);
  EXPECT_DOUBLE_EQ(horizon.min_range_m, 0.5);

  const SensorModel hap = sensor_model("hap");
  EXPECT_EQ(hap.pattern, ScanPattern::kRosette);
  EXPECT_DOUBLE_EQ(hap.fov_deg, 120);
  EXPECT_DOUBLE_EQ(hap.fov_v_deg, 25);
  EXPECT_EQ(points_per_frame(hap), 45200);

  const SensorModel mid360 = sensor_model("mid360");
  EXPECT_EQ(mid360.pattern, ScanPattern::kBand);
  EXPECT_DOUBLE_EQ(mid360.band_low_deg, -7);
  EXPECT_DOUBLE_EQ(mid360.band_high_deg, 52);
  EXPECT_EQ(mid360.band_beams, 4);
  EXPECT_EQ(points_per_frame(mid360), 20000);
  EXPECT_DOUBLE_EQ(mid360.min_range_m, 0.1);
  for (const SensorModel& s : {horizon, hap, mid360}) {
    EXPECT_DOUBLE_EQ(s.range_sigma_m, 0.02) << s.name;
    EXPECT_EQ(default_frames(s), 40) << s.name;
  }
  EXPECT_EQ(default_frames(sensor_model("vlp16")), 1);
}

TEST(LivoxWide, RosettesReachTheEdgesOfTheirWideFields) {
  // A wall 3 m ahead, 30 m square: wider than the HAP's 60 deg half-angle reaches (5.2 m).
  const Scene wall = testing::plain_wall(3, 30, 50);
  SimOptions o;
  o.frames = 2;
  o.range_sigma_m = 0;
  for (const SensorModel& s : {horizon(), hap()}) {
    SCOPED_TRACE(s.name);
    const SimResult r = simulate(wall, s, o);
    ASSERT_EQ(r.cloud.size(), static_cast<std::size_t>(points_per_frame(s)) * 2);
    double max_azimuth = 0, max_elevation = 0;
    for (std::size_t i = 0; i < r.cloud.size(); ++i) {
      const Vec3 p = r.cloud.point(i);
      max_azimuth = std::max(max_azimuth, std::abs(azimuth_deg(p)));
      max_elevation = std::max(max_elevation, std::abs(std::atan2(p.z(), p.x()) * kRadToDeg));
    }
    EXPECT_NEAR(max_azimuth, s.fov_deg / 2, 0.3);
    EXPECT_NEAR(max_elevation, s.fov_v_deg / 2, 0.3);
  }
}

// A 20 m cube around the Mid-360: every beam returns.
SimResult mid360_in_a_box(int frames) {
  Scene scene;
  scene.walls = box_walls(Vec3::Zero(), Vec3(20, 20, 20), 0, 50);
  SimOptions o;
  o.frames = frames;
  o.range_sigma_m = 0;
  return simulate(scene, mid360(), o);
}

TEST(LivoxWide, Mid360SweepsItsBandAllAroundEveryFrame) {
  const SimResult r = mid360_in_a_box(1);
  ASSERT_EQ(r.cloud.size(), 20000u);
  double lowest = 90, highest = -90;
  std::vector<int> per_degree(360, 0);
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Vec3 p = r.cloud.point(i);
    lowest = std::min(lowest, elevation_deg(p));
    highest = std::max(highest, elevation_deg(p));
    ++per_degree[static_cast<std::size_t>(
        std::clamp(std::floor(azimuth_deg(p) + 180), 0.0, 359.0))];
  }
  EXPECT_NEAR(lowest, -7, 0.2);
  EXPECT_NEAR(highest, 52, 0.2);
  // One turn a frame: each degree of azimuth gets its share (55 points), none is skipped.
  const auto [fewest, most] = std::minmax_element(per_degree.begin(), per_degree.end());
  EXPECT_GE(*fewest, 45);
  EXPECT_LE(*most, 65);
  // Point k fires at k / 200 000 s; the frame starts behind the sensor and turns anticlockwise.
  EXPECT_DOUBLE_EQ(r.cloud.time[0], 0);
  EXPECT_NEAR(r.cloud.time.back(), 19999.0 / 200000, 1e-12);
  EXPECT_NEAR(std::abs(azimuth_deg(r.cloud.point(0))), 180, 0.1);
  EXPECT_NEAR(azimuth_deg(r.cloud.point(10000)), 0, 0.1);
}

// Fraction of the 0.2 deg cells of the band (the preset's image) that hold a point.
double band_coverage(const PointCloud& cloud) {
  const double res = 0.2;
  const int columns = 1800, rows = static_cast<int>(std::lround(59 / res));
  std::vector<char> hit(static_cast<std::size_t>(columns) * rows, 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 p = cloud.point(i);
    const int u = std::clamp(static_cast<int>((azimuth_deg(p) + 180) / res), 0, columns - 1);
    const int v = std::clamp(static_cast<int>((elevation_deg(p) + 7) / res), 0, rows - 1);
    hit[static_cast<std::size_t>(v) * columns + u] = 1;
  }
  return static_cast<double>(std::count(hit.begin(), hit.end(), 1)) / hit.size();
}

TEST(LivoxWide, Mid360FramesNeverRepeatSoTheBandFillsIn) {
  std::vector<double> coverage;
  for (int frames : {1, 10, 40}) {
    const SimResult r = mid360_in_a_box(frames);
    coverage.push_back(band_coverage(r.cloud));
    // Uniformly random directions would cover 1 - exp(-points / cells).
    const double random = 1 - std::exp(-20000.0 * frames / (1800 * 295));
    std::cout << "[ measured ] Mid-360 " << frames << " frames: " << coverage.back()
              << " of the 0.2 deg band covered (uniformly random directions: " << random << ")\n";
    EXPECT_NEAR(coverage.back(), random, 0.05 * random) << frames;
  }
  // A pattern that repeated would stay at the first frame's coverage.
  EXPECT_GT(coverage[1], 8 * coverage[0]);
  EXPECT_GT(coverage[2], 2.4 * coverage[1]);
}

TEST(LivoxWide, Mid360GroundTruthUsesTheBand) {
  // Markers 3 m away at 45 deg up (inside), 55 deg up and 10 deg down (outside), and behind.
  const double d = 3;
  auto at = [&](int id, double azimuth, double elevation) {
    const Vec3 centre = d * Vec3(std::cos(elevation) * std::cos(azimuth),
                                 std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    const Wall board = upright_wall(centre, azimuth * kRadToDeg + 180, 0.3, 0.3);
    return marker_on_wall(board, "apriltag:tag36h11", id, 0.1, 0, 0);
  };
  Scene scene;
  scene.markers = {at(0, 0, 45 / kRadToDeg), at(1, 0, 55 / kRadToDeg), at(2, 0, -10 / kRadToDeg),
                   at(3, M_PI, 0)};
  const GroundTruth truth = ground_truth(scene, mid360(), SimOptions{});
  EXPECT_TRUE(truth.markers[0].visible);
  EXPECT_FALSE(truth.markers[1].visible);
  EXPECT_FALSE(truth.markers[2].visible);
  EXPECT_TRUE(truth.markers[3].visible);
}

}  // namespace
}  // namespace iilfm::sim
