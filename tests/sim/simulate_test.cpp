// Ray casting, the printed pattern, noise and determinism of simulate().
#include <gtest/gtest.h>

#include <cmath>

#include "iilfm/error.hpp"
#include "iilfm/sim/sim.hpp"

namespace iilfm::sim {
namespace {

SimOptions noise_free(int frames) {
  SimOptions o;
  o.frames = frames;
  o.range_sigma_m = 0;
  o.intensity_sigma = 0;
  return o;
}

// A wall filling the Mid-40's whole cone, `distance` ahead of a LiDAR at the origin.
Scene big_wall_at(double distance) {
  Wall w;
  w.T_world_wall.linear() = facing_minus_x();
  w.T_world_wall.translation() = Vec3(distance, 0, 0);
  w.width_m = w.height_m = 4 * distance;
  w.reflectivity = 50;
  Scene s;
  s.walls = {w};
  return s;
}

TEST(Simulate, SameSeedSameCloudOtherSeedOtherNoise) {
  const SceneSetup setup = named_scene("tag-wall");
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  o.frames = 3;
  o.angle_sigma_deg = 0.01;
  const SimResult a = simulate(setup.scene, mid40(), o);
  const SimResult b = simulate(setup.scene, mid40(), o);
  ASSERT_GT(a.cloud.size(), 20000u);
  EXPECT_EQ(a.cloud.x, b.cloud.x);
  EXPECT_EQ(a.cloud.y, b.cloud.y);
  EXPECT_EQ(a.cloud.z, b.cloud.z);
  EXPECT_EQ(a.cloud.intensity, b.cloud.intensity);
  EXPECT_EQ(a.cloud.time, b.cloud.time);
  o.seed = 2;
  const SimResult c = simulate(setup.scene, mid40(), o);
  EXPECT_NE(a.cloud.x, c.cloud.x);
}

TEST(Simulate, NoiseFreeHitsLieOnTheWallAndTheFloor) {
  const SceneSetup setup = named_scene("tag-wall");
  SimOptions o = noise_free(10);
  o.T_world_lidar = setup.T_world_lidar;
  const SimResult r = simulate(setup.scene, mid40(), o);
  ASSERT_GT(r.cloud.size(), 90000u);  // the wall and floor fill the whole cone
  std::size_t on_wall = 0, on_floor = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Vec3 p = o.T_world_lidar * r.cloud.point(i);
    const double to_wall = std::abs(p.x() - 3.62), to_floor = std::abs(p.z());
    ASSERT_LT(std::min(to_wall, to_floor), 1e-6) << "point " << i << ": " << p.transpose();
    (to_wall < to_floor ? on_wall : on_floor)++;
  }
  EXPECT_GT(on_wall, 0u);
  EXPECT_GT(on_floor, 0u);
}

// Every return inside the printed sheet carries the colour of the libapriltag cell it fell in.
TEST(Simulate, IntensitiesFollowThePrintedBitPattern) {
  const SceneSetup setup = named_scene("tag-wall");
  const Scene& scene = setup.scene;
  SimOptions o = noise_free(40);
  o.T_world_lidar = setup.T_world_lidar;
  const SimResult r = simulate(scene, mid40(), o);
  const MarkerTexture texture = render_marker_texture("apriltag:tag36h11", 0);
  const double cell = 0.172 / 8;
  const Isometry3 T_marker_lidar = scene.markers[0].T_world_marker.inverse() * o.T_world_lidar;
  std::size_t checked = 0, black_border_hits = 0, quiet_zone_hits = 0, wall_hits = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Vec3 m = T_marker_lidar * r.cloud.point(i);
    const double u = m.x() / cell + 5, v = 5 - m.y() / cell;  // image column and row
    const double edge =
        std::min({u - std::floor(u), std::ceil(u) - u, v - std::floor(v), std::ceil(v) - v});
    if (edge < 1e-3) continue;  // too close to a cell boundary for float coordinates
    const float value = r.cloud.intensity[i];
    if (u < 0 || u >= 10 || v < 0 || v >= 10) {
      if (std::abs(m.x()) < 0.5 && std::abs(m.y()) < 0.4 && std::abs(m.z()) < 1e-4) {
        EXPECT_EQ(value, 60.0f);  // bare wall around the sheet
        ++wall_hits;
      }
      continue;
    }
    const int col = static_cast<int>(u), row = static_cast<int>(v);
    const float expected = texture.is_black(row, col) ? 10.0f : 120.0f;
    ASSERT_EQ(value, expected) << "row " << row << " col " << col;
    ++checked;
    // The centre of the top-left black border cell, and the quiet zone's top-left cell.
    if (std::hypot(u - 1.5, v - 1.5) < 0.3) {
      EXPECT_EQ(value, scene.black_intensity);
      ++black_border_hits;
    }
    if (std::hypot(u - 0.5, v - 0.5) < 0.3) {
      EXPECT_EQ(value, scene.white_intensity);
      ++quiet_zone_hits;
    }
  }
  EXPECT_GT(checked, 5000u);
  EXPECT_GT(black_border_hits, 10u);
  EXPECT_GT(quiet_zone_hits, 10u);
  EXPECT_GT(wall_hits, 1000u);
  EXPECT_GT(r.truth.markers[0].points_on_marker, 5000u);
}

TEST(Simulate, MarkersShowOnlyOnTheirPrintedFace) {
  Scene scene = big_wall_at(3);
  MarkerSpec back = wall_marker("apriltag:tag36h11", 0, 0.5, 3, 0, 0);
  // Turned about the vertical: the printed face looks away from the LiDAR, along +x.
  back.T_world_marker.linear() =
      Eigen::AngleAxisd(M_PI, Vec3::UnitZ()).toRotationMatrix() * back.T_world_marker.linear();
  scene.markers = {back};
  const SimResult r = simulate(scene, mid40(), noise_free(2));
  for (float v : r.cloud.intensity) ASSERT_EQ(v, 50.0f);
  EXPECT_FALSE(r.truth.markers[0].visible);
  EXPECT_EQ(r.truth.markers[0].points_on_marker, 0u);
}

TEST(Simulate, RangeNoiseHasTheConfiguredSigma) {
  const Scene scene = big_wall_at(5);
  SimOptions o;
  o.frames = 10;
  o.range_sigma_m = 0.02;
  const SimResult r = simulate(scene, mid40(), o);
  double sum = 0, sum_sq = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Vec3 p = r.cloud.point(i);
    const double error = p.norm() - 5.0 * p.norm() / p.x();  // measured minus true range
    sum += error;
    sum_sq += error * error;
  }
  const double n = static_cast<double>(r.cloud.size());
  const double mean = sum / n, sigma = std::sqrt(sum_sq / n - mean * mean);
  std::cout << "[ measured ] range noise sigma " << sigma << " m (configured 0.02), mean " << mean
            << " m over " << r.cloud.size() << " points\n";
  EXPECT_NEAR(sigma, 0.02, 0.002);
  EXPECT_NEAR(mean, 0, 0.001);
}

TEST(Simulate, SensorDefaultSigmaAppliesWhenOptionIsNegative) {
  const Scene scene = big_wall_at(5);
  SimOptions o;
  o.frames = 5;
  const SimResult r = simulate(scene, vlp16(), o);
  EXPECT_DOUBLE_EQ(r.truth.range_sigma_m, 0.03);
}

TEST(Simulate, IntensityNoiseHasTheConfiguredSigma) {
  const Scene scene = big_wall_at(5);
  SimOptions o;
  o.frames = 10;
  o.intensity_sigma = 4;
  const SimResult r = simulate(scene, mid40(), o);
  double sum = 0, sum_sq = 0;
  for (float v : r.cloud.intensity) {
    sum += v - 50.0;
    sum_sq += (v - 50.0) * (v - 50.0);
  }
  const double n = static_cast<double>(r.cloud.size());
  EXPECT_NEAR(std::sqrt(sum_sq / n - (sum / n) * (sum / n)), 4.0, 0.2);
}

TEST(Simulate, IntensityNeverGoesNegative) {
  Scene scene = big_wall_at(5);
  scene.walls[0].reflectivity = 1;
  SimOptions o;
  o.intensity_sigma = 10;
  const SimResult r = simulate(scene, mid40(), o);
  for (float v : r.cloud.intensity) ASSERT_GE(v, 0.0f);
}

TEST(Simulate, ReturnsCloserThanMinRangeAreDroppedAndBlockTheView) {
  Scene scene = big_wall_at(10);
  Scene near = big_wall_at(0.8);  // inside the Mid-40's 1 m blind zone
  scene.walls.push_back(near.walls[0]);
  EXPECT_TRUE(simulate(scene, mid40(), noise_free(1)).cloud.empty());
}

TEST(Simulate, BeamsThatHitNothingReturnNothing) {
  EXPECT_TRUE(simulate(Scene{}, mid40(), noise_free(1)).cloud.empty());
  Scene behind = big_wall_at(-5);  // the Mid-40 looks along +x only
  EXPECT_TRUE(simulate(behind, mid40(), noise_free(1)).cloud.empty());
}

TEST(Simulate, PointsAreInTheLidarFrame) {
  // The same geometry seen from a LiDAR moved and turned in the world gives the same cloud.
  const Scene here = big_wall_at(4);
  Isometry3 T = Isometry3::Identity();
  T.linear() = Eigen::AngleAxisd(0.7, Vec3(0.2, -0.3, 1).normalized()).toRotationMatrix();
  T.translation() = Vec3(1, -2, 3);
  Scene there = here;
  there.walls[0].T_world_wall = T * here.walls[0].T_world_wall;
  SimOptions o = noise_free(1);
  const SimResult a = simulate(here, mid40(), o);
  o.T_world_lidar = T;
  const SimResult b = simulate(there, mid40(), o);
  ASSERT_EQ(a.cloud.size(), b.cloud.size());
  for (std::size_t i = 0; i < a.cloud.size(); i += 97) {
    ASSERT_NEAR((a.cloud.point(i) - b.cloud.point(i)).norm(), 0, 1e-5);
  }
}

TEST(Simulate, BadInputsAreInputErrors) {
  Scene scene = big_wall_at(3);
  SimOptions o;
  o.frames = 0;
  EXPECT_THROW(simulate(scene, mid40(), o), InputError);
  scene.markers = {wall_marker("apriltag:tag36h11", 0, 0.2, 3, 0, 0)};
  scene.markers[0].size_m = 0;
  EXPECT_THROW(simulate(scene, mid40(), SimOptions{}), InputError);
  scene.markers[0].size_m = 0.2;
  scene.markers[0].family = "aruco:DICT_4X4_51";
  EXPECT_THROW(simulate(scene, mid40(), SimOptions{}), InputError);
  scene.markers[0].family = "aruco:DICT_4X4_50";
  scene.markers[0].id = 50;
  EXPECT_THROW(simulate(scene, mid40(), SimOptions{}), InputError);
  scene.markers[0].family = "apriltag:tag36h11";
  scene.markers[0].id = 587;  // tag36h11 has 587 codes
  EXPECT_THROW(simulate(scene, mid40(), SimOptions{}), InputError);
}

}  // namespace
}  // namespace iilfm::sim
