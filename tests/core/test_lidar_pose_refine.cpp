// The LiDAR pose refinement on corner rays and marker-plane points (refine_lidar_pose), on
// synthetic markers made the way the plane lift makes them: a plane fitted with a known offset
// and slope error, and corners where rays with in-plane detection error meet that plane.
#include <gtest/gtest.h>

#include <random>

#include "iilfm/lidar_pose.hpp"
#include "iilfm/pose.hpp"

namespace iilfm {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

struct MarkerPlacement {
  Vec3 centre;        // world
  double facing_deg;  // azimuth of the wall's normal (pointing into the room)
  double size;
};

struct Noise {
  double in_plane_m = 0.0005;  // detection error of each corner, per in-plane axis
  double offset_m = 0.0003;    // plane offset sigma at the marker's centre
  double slope_rad = 0.0015;   // plane slope sigma per in-plane axis
  double per_metre = 0.3;      // all three grow by this fraction per metre of range
};

struct Synthetic {
  Isometry3 T_world_lidar = Isometry3::Identity();
  std::vector<MarkerCorrespondence> markers;
};

Isometry3 lidar_pose() {
  Isometry3 T = Isometry3::Identity();
  T.linear() = rotation_from_rpy_deg(Vec3(1, -2, 20));
  T.translation() = Vec3(0.3, -0.4, 1.2);
  return T;
}

// Markers near (2 m) and far (8 m) on walls facing several ways, seen by a LiDAR at the origin
// of lidar_pose(); `tilt_deg` tilts the fitted plane of marker `tilted` (about its axis1) beyond
// its noise, with its corners lifted onto the true plane.
Synthetic make(std::uint32_t seed, const Noise& noise, int tilted = -1, double tilt_deg = 0) {
  const std::vector<MarkerPlacement> placements = {{Vec3(2.2, 0.9, 1.1), 200, 0.3},
                                                   {Vec3(5.0, 3.5, 1.6), 230, 0.3},
                                                   {Vec3(-1.5, 7.5, 0.8), 280, 0.5},
                                                   {Vec3(7.0, -3.0, 1.4), 170, 0.5}};
  Synthetic s;
  s.T_world_lidar = lidar_pose();
  const Isometry3 T_lidar_world = s.T_world_lidar.inverse();
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0, 1);
  for (std::size_t i = 0; i < placements.size(); ++i) {
    const MarkerPlacement& p = placements[i];
    Isometry3 T_world_marker = Isometry3::Identity();
    // Marker z (out of the face) along the wall's normal, x horizontal, y up.
    const double a = p.facing_deg * M_PI / 180;
    const Vec3 z(std::cos(a), std::sin(a), 0), y = Vec3::UnitZ(), x = y.cross(z);
    T_world_marker.linear() << x, y, z;
    T_world_marker.translation() = p.centre;
    MarkerCorrespondence m;
    m.key = "apriltag:tag36h11/" + std::to_string(i);
    std::vector<Vec3> truth;
    for (const Vec3& c : marker_frame_corners(p.size)) {
      m.world.push_back(T_world_marker * c);
      truth.push_back(T_lidar_world * m.world.back());
    }
    // The fitted plane: the true one moved by (offset, slope1, slope2) about the centre.
    const Vec3 centre = T_lidar_world * p.centre;
    const double range_scale = 1 + noise.per_metre * centre.norm();
    Vec3 normal = T_lidar_world.linear() * z;
    if (normal.dot(centre) > 0) normal = -normal;
    const Vec3 axis1 = T_lidar_world.linear() * x, axis2 = normal.cross(axis1);
    const double offset = noise.offset_m * range_scale * gauss(rng);
    double slope1 = noise.slope_rad * range_scale * gauss(rng);
    const double slope2 = noise.slope_rad * range_scale * gauss(rng);
    if (static_cast<int>(i) == tilted) slope1 += std::tan(tilt_deg * M_PI / 180);
    Plane plane;
    plane.normal = (normal - slope1 * axis1 - slope2 * axis2).normalized();
    plane.centre = centre + offset * normal;
    plane.d = plane.normal.dot(plane.centre);
    plane.axis1 = (axis1 - axis1.dot(plane.normal) * plane.normal).normalized();
    plane.axis2 = plane.normal.cross(plane.axis1);
    plane.offset_variance = std::pow(noise.offset_m * range_scale, 2);
    plane.slope_variance.setConstant(std::pow(noise.slope_rad * range_scale, 2));
    plane.ok = true;
    const double in_plane = noise.in_plane_m * range_scale;
    // The tilted marker's corners stay on the true plane: only its plane term is wrong.
    Plane lift_plane = plane;
    if (static_cast<int>(i) == tilted) {
      lift_plane.normal = normal;
      lift_plane.d = normal.dot(centre);
    }
    for (const Vec3& t : truth) {
      const Vec3 seen = t + in_plane * (gauss(rng) * axis1 + gauss(rng) * axis2);
      const Vec3 ray = seen.normalized();
      m.lidar.push_back(ray * (lift_plane.d / lift_plane.normal.dot(ray)));
    }
    m.lidar_covariance = plane_corner_covariance(m.lidar, lift_plane, in_plane);
    m.plane = plane;
    s.markers.push_back(std::move(m));
  }
  return s;
}

Vec6 pose_error(const Isometry3& estimate, const Isometry3& truth) {
  Vec6 e;
  const Eigen::AngleAxisd aa(Mat3(estimate.linear().transpose() * truth.linear()));
  e.head<3>() = aa.angle() * aa.axis();
  e.tail<3>() = truth.translation() - estimate.translation();
  return e;
}

LidarPoseOptions with(PoseRefine refine) {
  LidarPoseOptions options;
  options.refine = refine;
  return options;
}

TEST(LidarPoseRefine, ExactDataGivesTheExactPoseFromAFarStart) {
  Noise none;
  none.in_plane_m = none.offset_m = none.slope_rad = 0;
  Synthetic s = make(1, none);
  for (MarkerCorrespondence& m : s.markers) {  // zero noise: tiny, equal variances
    m.lidar_covariance = plane_corner_covariance(m.lidar, *m.plane, 1e-4);
    m.plane->offset_variance = 1e-8;
    m.plane->slope_variance.setConstant(1e-8);
  }
  Isometry3 start = s.T_world_lidar;
  start.linear() = start.linear() * rotation_from_rpy_deg(Vec3(0.5, -0.3, 0.4));
  start.translation() += Vec3(0.02, -0.01, 0.015);
  const PoseRefinement r = refine_lidar_pose(s.markers, start, Mat6::Identity());
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.planes_used.size(), 4u);
  EXPECT_LT(pose_error(r.T_world_lidar, s.T_world_lidar).norm(), 1e-9);
  EXPECT_LT(r.chi2, 1e-12);
}

// Over many draws the refined pose errs less than Kabsch (near and far markers: Kabsch weighs
// the far markers' noisier corners like the near ones, and a corner's depth like its in-plane
// position), and its covariance matches its error: mean NEES near 6.
TEST(LidarPoseRefine, BeatsKabschAndClaimsItsError) {
#ifdef NDEBUG
  const int trials = 300;
#else
  const int trials = 20;  // sanitizer builds: the code paths, not the statistics
#endif
  double kabsch_rot = 0, refined_rot = 0, kabsch_pos = 0, refined_pos = 0, nees = 0;
  for (int t = 0; t < trials; ++t) {
    const Synthetic s = make(static_cast<std::uint32_t>(t), Noise{});
    const LidarPoseResult k = estimate_lidar_pose(s.markers, with(PoseRefine::kNone));
    const LidarPoseResult r = estimate_lidar_pose(s.markers, with(PoseRefine::kPoints));
    ASSERT_TRUE(k.ok && r.ok) << k.failure << r.failure;
    ASSERT_EQ(r.pose.planes_used.size(), 4u)
        << "trial " << t << ": " << r.pose.markers_used.size() << " markers used";
    const Vec6 ek = pose_error(k.pose.T_world_lidar, s.T_world_lidar);
    const Vec6 er = pose_error(r.pose.T_world_lidar, s.T_world_lidar);
    kabsch_rot += ek.head<3>().squaredNorm();
    refined_rot += er.head<3>().squaredNorm();
    kabsch_pos += ek.tail<3>().squaredNorm();
    refined_pos += er.tail<3>().squaredNorm();
    nees += er.dot(r.pose.covariance.ldlt().solve(er));
  }
  const double deg = 180 / M_PI;
  std::printf(
      "RMS rotation Kabsch %.4f deg, refined %.4f deg; position %.2f / %.2f mm; NEES %.2f\n",
      std::sqrt(kabsch_rot / trials) * deg, std::sqrt(refined_rot / trials) * deg,
      std::sqrt(kabsch_pos / trials) * 1000, std::sqrt(refined_pos / trials) * 1000, nees / trials);
  // Measured: rotation 0.0147 -> 0.0142 deg, position 1.11 -> 0.97 mm, NEES 6.04.
#ifdef NDEBUG
  EXPECT_LT(refined_rot, kabsch_rot);
  EXPECT_LT(refined_pos, 0.92 * 0.92 * kabsch_pos);
  EXPECT_NEAR(nees / trials, 6.0, 1.0);
#endif
}

// A plane tilted 3 degrees against its own corners is left out, not averaged in: the pose stays
// as good as without that plane, and the marker's corners still count.
TEST(LidarPoseRefine, ATiltedPlaneIsLeftOut) {
  double error_tilted = 0, error_clean = 0;
  for (std::uint32_t seed = 0; seed < 20; ++seed) {
    const Synthetic clean = make(seed, Noise{});
    const Synthetic tilted = make(seed, Noise{}, 2, 3.0);
    const LidarPoseResult r = estimate_lidar_pose(tilted.markers, with(PoseRefine::kPoints));
    ASSERT_TRUE(r.ok) << r.failure;
    ASSERT_EQ(r.pose.planes_rejected.size(), 1u) << "seed " << seed;
    EXPECT_EQ(r.pose.planes_rejected[0], "apriltag:tag36h11/2");
    EXPECT_EQ(r.pose.markers_used.size(), 4u);
    error_tilted += pose_error(r.pose.T_world_lidar, tilted.T_world_lidar).head<3>().norm();
    const LidarPoseResult c = estimate_lidar_pose(clean.markers, with(PoseRefine::kPoints));
    error_clean += pose_error(c.pose.T_world_lidar, clean.T_world_lidar).head<3>().norm();
  }
  // A 3 degree pull shared by four markers would be ~0.75 degree (13 mrad); the left-out plane
  // costs only its own information.
  EXPECT_LT(error_tilted / 20, 2 * error_clean / 20);
  EXPECT_LT(error_tilted / 20, 0.002);
}

// One marker whose plane disagrees with its corners: nothing outvotes it, so the refinement may
// not move the pose further than the corners' own covariance allows; it keeps the Kabsch pose.
TEST(LidarPoseRefine, OneMarkersPlaneCannotPullThePoseBeyondItsCorners) {
  const Synthetic s = make(5, Noise{}, 0, 3.0);
  const std::vector<MarkerCorrespondence> one = {s.markers[0]};
  const LidarPoseResult k = estimate_lidar_pose(one, with(PoseRefine::kNone));
  const LidarPoseResult r = estimate_lidar_pose(one, with(PoseRefine::kPoints));
  ASSERT_TRUE(k.ok && r.ok);
  EXPECT_EQ(r.pose.planes_used.size(), 0u);
  EXPECT_EQ(r.pose.planes_rejected.size(), 1u);
  EXPECT_LT((r.pose.T_world_lidar.matrix() - k.pose.T_world_lidar.matrix()).norm(), 1e-12);
  // Without the tilt the same marker's plane is used and agrees with its corners.
  const Synthetic straight = make(5, Noise{});
  const LidarPoseResult u = estimate_lidar_pose({straight.markers[0]}, with(PoseRefine::kPoints));
  ASSERT_TRUE(u.ok);
  EXPECT_EQ(u.pose.planes_used.size(), 1u);
}

TEST(LidarPoseRefine, WithoutPlanesNothingIsRefined) {
  Synthetic s = make(3, Noise{});
  for (MarkerCorrespondence& m : s.markers) m.plane.reset();
  const LidarPoseResult k = estimate_lidar_pose(s.markers, with(PoseRefine::kNone));
  const LidarPoseResult r = estimate_lidar_pose(s.markers, with(PoseRefine::kPoints));
  ASSERT_TRUE(k.ok && r.ok);
  EXPECT_TRUE(r.pose.planes_used.empty());
  EXPECT_LT((r.pose.T_world_lidar.matrix() - k.pose.T_world_lidar.matrix()).norm(), 1e-12);
  EXPECT_LT((r.pose.covariance - k.pose.covariance).norm(), 1e-15);
}

}  // namespace
}  // namespace iilfm
