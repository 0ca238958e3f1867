// A moving sensor: each beam is cast from the pose at its own time stamp and written in the
// LiDAR frame of that time, so a wall comes out skewed by exactly the motion.
#include <gtest/gtest.h>

#include <cmath>

#include "iilfm/error.hpp"
#include "iilfm/sim/sim.hpp"
#include "plain_wall.hpp"

namespace iilfm::sim {
namespace {

SimOptions noise_free() {
  SimOptions o;
  o.range_sigma_m = 0;
  o.intensity_sigma = 0;
  return o;
}

TEST(Motion, ZeroVelocityChangesNothing) {
  const SceneSetup setup = named_scene("tag-wall");
  SimOptions still = noise_free();
  still.T_world_lidar = setup.T_world_lidar;
  still.frames = 2;
  still.footprint = true;
  SimOptions zero = still;
  zero.linear_velocity = Vec3::Zero();
  zero.angular_velocity = Vec3::Zero();
  const SimResult a = simulate(setup.scene, mid40(), still);
  const SimResult b = simulate(setup.scene, mid40(), zero);
  ASSERT_EQ(a.cloud.size(), b.cloud.size());
  for (std::size_t i = 0; i < a.cloud.size(); ++i) {
    ASSERT_EQ(a.cloud.x[i], b.cloud.x[i]);
    ASSERT_EQ(a.cloud.intensity[i], b.cloud.intensity[i]);
  }
  EXPECT_EQ(a.truth.markers[0].points_on_marker, b.truth.markers[0].points_on_marker);
  EXPECT_TRUE(lidar_pose_at(zero, 0.37).isApprox(zero.T_world_lidar));

  // A crawl of 1 um/s goes through the moving code path (rays off the origin, no culling
  // cones) and must give the same scan to well below a millimetre.
  SimOptions crawl = still;
  crawl.linear_velocity = Vec3(1e-6, 0, 0);
  const SimResult c = simulate(setup.scene, mid40(), crawl);
  ASSERT_EQ(a.cloud.size(), c.cloud.size());
  for (std::size_t i = 0; i < a.cloud.size(); ++i) {
    ASSERT_LT((a.cloud.point(i) - c.cloud.point(i)).norm(), 1e-5) << i;
    ASSERT_EQ(a.cloud.intensity[i], c.cloud.intensity[i]) << i;
  }
  EXPECT_EQ(a.truth.markers[0].points_on_marker, c.truth.markers[0].points_on_marker);
}

TEST(Motion, DrivingTowardsAWallSkewsEachPointByItsOwnTime) {
  const Scene wall = testing::plain_wall(5, 40, 50);
  SimOptions o = noise_free();
  o.linear_velocity = Vec3(2, 0, 0);  // 2 m/s straight at the wall
  const SimResult r = simulate(wall, vlp16(), o);
  ASSERT_GT(r.cloud.size(), 5000u);
  double nearest = 1e9, farthest = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    // Fired at t, the LiDAR is 2t closer: the wall reads x = 5 - 2t in the frame of that time.
    const double expected = 5 - 2 * r.cloud.time[i];
    ASSERT_NEAR(r.cloud.x[i], expected, 1e-5) << i << " t " << r.cloud.time[i];
    nearest = std::min(nearest, static_cast<double>(r.cloud.x[i]));
    farthest = std::max(farthest, static_cast<double>(r.cloud.x[i]));
  }
  // The front half of the sweep spans about 0.05 s: a 10 cm skew across the wall.
  EXPECT_GT(farthest - nearest, 0.08);
  // The ground truth keeps the pose at time 0; lidar_pose_at gives the later ones.
  EXPECT_TRUE(r.truth.T_world_lidar.isApprox(Isometry3::Identity()));
  EXPECT_NEAR(lidar_pose_at(o, 0.1).translation().x(), 0.2, 1e-12);
}

TEST(Motion, TurningSkewsARosetteAndTheStartPoseUndoesIt) {
  const Scene wall = testing::plain_wall(5, 40, 50);
  SimOptions o = noise_free();
  o.T_world_lidar.translation() = Vec3(0, 0, 0.3);  // a world pose away from the origin
  o.linear_velocity = Vec3(0.5, 0.2, 0);
  o.angular_velocity = Vec3(0, 0, 1.0);  // 1 rad/s yaw: 5.7 deg over one frame
  const SimResult r = simulate(wall, mid40(), o);
  ASSERT_EQ(r.cloud.size(), 10000u);
  double worst_raw = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    // Back into the world through the pose at the point's own time: on the wall plane x = 5.
    const Vec3 world = lidar_pose_at(o, r.cloud.time[i]) * r.cloud.point(i).cast<double>();
    ASSERT_NEAR(world.x(), 5, 1e-5) << i;
    // Taken as if the sensor had stood still, the points leave the plane.
    const Vec3 naive = o.T_world_lidar * r.cloud.point(i).cast<double>();
    worst_raw = std::max(worst_raw, std::abs(naive.x() - 5));
  }
  EXPECT_GT(worst_raw, 0.05);
}

TEST(Motion, NonFiniteVelocityIsRejected) {
  SimOptions o;
  o.angular_velocity.x() = std::nan("");
  EXPECT_THROW(simulate(testing::plain_wall(5, 10, 50), vlp16(), o), InputError);
}

}  // namespace
}  // namespace iilfm::sim
