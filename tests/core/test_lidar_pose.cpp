#include <gtest/gtest.h>

#include <random>

#include "iilfm/lidar_pose.hpp"
#include "iilfm/pose.hpp"

namespace iilfm {
namespace {

// `count` 17 cm markers on a wall 4 m ahead of a LiDAR at T_world_lidar, with corner noise.
struct Scene {
  Isometry3 T_world_lidar = Isometry3::Identity();
  std::vector<MarkerCorrespondence> markers;
};

Scene make_scene(int count, double noise_m, std::uint32_t seed) {
  Scene s;
  s.T_world_lidar.linear() = rotation_from_rpy_deg(Vec3(2, -3, 10));
  s.T_world_lidar.translation() = Vec3(0.5, -0.2, 1.1);
  const Isometry3 T_lidar_world = s.T_world_lidar.inverse();
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, noise_m);
  for (int i = 0; i < count; ++i) {
    MarkerCorrespondence m;
    m.key = "apriltag:tag36h11/" + std::to_string(i);
    const Vec3 centre(4.5, -1.0 + 0.5 * i, 1.0 + 0.3 * (i % 2));
    for (const Vec3& c : marker_frame_corners(0.172)) {
      const Vec3 world = centre + Vec3(0, -c.x(), c.y());  // on the wall x = 4.5, facing -x
      m.world.push_back(world);
      m.lidar.push_back(T_lidar_world * world + Vec3(noise(rng), noise(rng), noise(rng)));
    }
    s.markers.push_back(m);
  }
  return s;
}

double position_error(const LidarPose& pose, const Scene& s) {
  return (pose.T_world_lidar.translation() - s.T_world_lidar.translation()).norm();
}

TEST(LidarPose, RecoversThePoseFromOneOrManyMarkers) {
  for (int count : {1, 2, 5}) {
    const Scene s = make_scene(count, 0.0, 1);
    const LidarPoseResult r = estimate_lidar_pose(s.markers);
    ASSERT_TRUE(r.ok) << r.failure;
    EXPECT_LT(position_error(r.pose, s), 1e-9);
    EXPECT_EQ(r.pose.markers_used.size(), static_cast<std::size_t>(count));
    EXPECT_EQ(r.pose.corners_used, 4u * count);
    EXPECT_TRUE(r.pose.markers_rejected.empty());
  }
}

TEST(LidarPose, DropsAMovedMarkerInsteadOfAveragingIt) {
  Scene s = make_scene(5, 0.003, 2);
  for (Vec3& w : s.markers[3].world) w += Vec3(0, 0.15, 0);  // the map is wrong about marker 3
  const LidarPoseResult r = estimate_lidar_pose(s.markers);
  ASSERT_TRUE(r.ok) << r.failure;
  ASSERT_EQ(r.pose.markers_rejected.size(), 1u);
  EXPECT_EQ(r.pose.markers_rejected[0].key, "apriltag:tag36h11/3");
  EXPECT_NEAR(r.pose.markers_rejected[0].residual_m, 0.15, 0.02);
  EXPECT_EQ(r.pose.markers_used.size(), 4u);
  // Exactly the pose of the four good markers: the moved one left no trace.
  std::vector<MarkerCorrespondence> good = s.markers;
  good.erase(good.begin() + 3);
  const LidarPoseResult clean = estimate_lidar_pose(good);
  ASSERT_TRUE(clean.ok);
  EXPECT_LT((r.pose.T_world_lidar.matrix() - clean.pose.T_world_lidar.matrix()).norm(), 1e-12);
  EXPECT_LT(r.pose.rms, 0.01);
  EXPECT_LT(position_error(r.pose, s), 0.05);
}

TEST(LidarPose, RefusesTwoMarkersThatDisagree) {
  Scene s = make_scene(2, 0.0, 3);
  for (Vec3& w : s.markers[1].world) w += Vec3(0, 0, 0.3);
  const LidarPoseResult r = estimate_lidar_pose(s.markers);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("disagree"), std::string::npos) << r.failure;
}

TEST(LidarPose, MoreMarkersGiveASmallerError) {
  double error_one = 0, error_five = 0;
  for (std::uint32_t seed = 0; seed < 40; ++seed) {
    const Scene s = make_scene(5, 0.01, seed);
    error_five += position_error(estimate_lidar_pose(s.markers).pose, s);
    error_one += position_error(estimate_lidar_pose({s.markers[2]}).pose, s);
  }
  EXPECT_LT(error_five, 0.5 * error_one);
}

TEST(LidarPose, ExplainsMissingPoses) {
  EXPECT_EQ(estimate_lidar_pose({}).failure, "no mapped marker detected");
  Scene s = make_scene(1, 0.0, 4);
  s.markers[0].world.resize(3);
  s.markers[0].lidar.resize(3);
  const LidarPoseResult r = estimate_lidar_pose(s.markers);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("only 3 mapped corners"), std::string::npos) << r.failure;
}

}  // namespace
}  // namespace iilfm
