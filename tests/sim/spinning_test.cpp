// Spinning sensors: ring and time fields, ring elevations, sweep timing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "iilfm/sim/sim.hpp"

namespace iilfm::sim {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

SimResult scan_tag_wall(const SensorModel& sensor, int frames) {
  const SceneSetup setup = named_scene("tag-wall");
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  o.frames = frames;
  o.range_sigma_m = 0;
  o.intensity_sigma = 0;
  return simulate(setup.scene, sensor, o);
}

void expect_rings_at_table_elevations(const SensorModel& sensor) {
  const SimResult r = scan_tag_wall(sensor, 1);
  ASSERT_TRUE(r.cloud.has_ring());
  ASSERT_TRUE(r.cloud.has_time());
  ASSERT_EQ(r.cloud.ring.size(), r.cloud.size());
  ASSERT_EQ(r.cloud.time.size(), r.cloud.size());
  std::set<int> rings;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const int ring = r.cloud.ring[i];
    ASSERT_LT(ring, static_cast<int>(sensor.ring_elevations_deg.size()));
    rings.insert(ring);
    const Vec3 p = r.cloud.point(i);
    const double elevation = std::atan2(p.z(), std::hypot(p.x(), p.y())) * kRadToDeg;
    ASSERT_NEAR(elevation, sensor.ring_elevations_deg[ring], 0.01) << "point " << i;
    ASSERT_GE(r.cloud.time[i], 0.0);
    ASSERT_LT(r.cloud.time[i], 0.1);
  }
  EXPECT_EQ(rings.size(), sensor.ring_elevations_deg.size());
}

TEST(Spinning, Vlp16ReturnsAll16RingsAtTheirElevations) {
  expect_rings_at_table_elevations(vlp16());
}

TEST(Spinning, UltraPuckReturnsAll32RingsAtTheirElevations) {
  expect_rings_at_table_elevations(ultra_puck());
}

// Each ring fires at its model's azimuth offset, clockwise of its column: every point of ring r
// lies the same fraction of a column past the grid, frac(offset_r / step) (the VLP-16's rings
// 2.304 us apart in its firing order, the VLP-32C's and Pandar40P's manual offsets), and the
// tables give every ring one offset (the VLP-32C's are matched to its rings by elevation).
TEST(Spinning, EveryRingLiesAtItsFiringOffsetFromTheColumnGrid) {
  for (const SensorModel& sensor : {vlp16(), vlp16_hires(), ultra_puck(), hdl32e(), pandar40p()}) {
    SCOPED_TRACE(sensor.name);
    const std::size_t rings = sensor.ring_elevations_deg.size();
    ASSERT_EQ(sensor.ring_azimuth_offsets_deg.size(), rings);
    const SimResult r = scan_tag_wall(sensor, 1);
    std::vector<int> seen(rings, 0);
    for (std::size_t i = 0; i < r.cloud.size(); ++i) {
      const Vec3 p = r.cloud.point(i);
      const double columns =
          (180.0 - std::atan2(p.y(), p.x()) * kRadToDeg) / sensor.azimuth_step_deg;
      const double lag = sensor.ring_azimuth_offsets_deg[r.cloud.ring[i]] / sensor.azimuth_step_deg;
      double phase = (columns - std::floor(columns)) - (lag - std::floor(lag));
      phase -= std::round(phase);
      ASSERT_NEAR(phase, 0, 1e-3) << "ring " << r.cloud.ring[i];
      ++seen[r.cloud.ring[i]];
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 0), 0);
  }
  // The VLP-16: its -1 and +1 deg rings (7 and 8) fire 13 slots of 24 apart.
  const SensorModel v = vlp16();
  EXPECT_NEAR((v.ring_azimuth_offsets_deg[7] - v.ring_azimuth_offsets_deg[8]) / v.azimuth_step_deg,
              13.0 / 24, 1e-12);
}

// The head turns clockwise seen from above, starting behind the sensor: azimuth a fires at
// ((180 - a) mod 360) / 360 of the sweep.
TEST(Spinning, TimeFollowsTheAzimuthOfTheColumn) {
  const SimResult r = scan_tag_wall(vlp16(), 2);
  ASSERT_FALSE(r.cloud.empty());
  double latest = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Vec3 p = r.cloud.point(i);
    const double azimuth = std::atan2(p.y(), p.x()) * kRadToDeg;
    const double turned = std::fmod(180.0 - azimuth + 360.0, 360.0);
    const double sweep_time = std::fmod(r.cloud.time[i], 0.1);
    double error = sweep_time - turned / 360.0 * 0.1;
    error -= 0.1 * std::round(error / 0.1);  // azimuth 180 is both the start and the end
    ASSERT_NEAR(error, 0, 1e-4) << "azimuth " << azimuth;
    latest = std::max(latest, r.cloud.time[i]);
  }
  EXPECT_GT(latest, 0.1);  // the second sweep
  EXPECT_LT(latest, 0.2);
}

TEST(Spinning, RepeatedSweepsDrawNewNoise) {
  const SceneSetup setup = named_scene("tag-wall");
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  o.frames = 2;
  const SimResult r = simulate(setup.scene, vlp16(), o);
  const std::size_t half = r.cloud.size() / 2;
  ASSERT_EQ(r.cloud.size() % 2, 0u);  // the same beams return in both sweeps here
  EXPECT_NE(std::vector<float>(r.cloud.x.begin(), r.cloud.x.begin() + half),
            std::vector<float>(r.cloud.x.begin() + half, r.cloud.x.end()));
}

TEST(Rosette, FillsTimeButNoRing) {
  const SimResult r = scan_tag_wall(mid40(), 2);
  EXPECT_FALSE(r.cloud.has_ring());
  ASSERT_EQ(r.cloud.time.size(), r.cloud.size());
  for (double t : r.cloud.time) {
    ASSERT_GE(t, 0.0);
    ASSERT_LT(t, 0.2);
  }
}

}  // namespace
}  // namespace iilfm::sim
