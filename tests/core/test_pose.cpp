#include <gtest/gtest.h>

#include <random>

#include "iilfm/pose.hpp"

namespace iilfm {
namespace {

Isometry3 random_pose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Isometry3 T = Isometry3::Identity();
  T.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
  T.translation() = Vec3(u(rng), u(rng), u(rng)) * 10;
  return T;
}

std::vector<Vec3> random_points(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  return pts;
}

TEST(FitRigid, RecoversRandomTransformsExactly) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Isometry3 T = random_pose(rng);
    const auto src = random_points(rng, 3 + trial % 10);
    std::vector<Vec3> dst;
    for (const Vec3& p : src) dst.push_back(T * p);
    const RigidFit fit = fit_rigid(src, dst);
    ASSERT_TRUE(fit.ok);
    EXPECT_LT((fit.T.matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT(fit.rms, 1e-9);
  }
}

TEST(FitRigid, FourCoplanarMarkerCornersGiveAUniquePose) {
  std::mt19937 rng(3);
  const auto corners = marker_frame_corners(0.172);
  for (int trial = 0; trial < 50; ++trial) {
    const Isometry3 T = random_pose(rng);
    std::vector<Vec3> src(corners.begin(), corners.end()), dst;
    for (const Vec3& p : src) dst.push_back(T * p);
    const RigidFit fit = fit_rigid(src, dst);
    ASSERT_TRUE(fit.ok);
    EXPECT_LT((fit.T.matrix() - T.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(FitRigid, NoiseGivesMatchingRms) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 0.01);
  const Isometry3 T = random_pose(rng);
  const auto src = random_points(rng, 2000);
  std::vector<Vec3> dst;
  for (const Vec3& p : src) dst.push_back(T * p + Vec3(noise(rng), noise(rng), noise(rng)));
  const RigidFit fit = fit_rigid(src, dst);
  ASSERT_TRUE(fit.ok);
  // 3-D residual of isotropic 1 cm noise: sqrt(3) * 1 cm, less the 6 fitted degrees of freedom.
  EXPECT_NEAR(fit.rms, std::sqrt(3.0) * 0.01, 0.001);
  EXPECT_LT((fit.T.translation() - T.translation()).norm(), 0.003);
}

TEST(FitRigid, MirroredInputNeverYieldsAReflection) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const auto src = random_points(rng, 6);
    std::vector<Vec3> dst;
    for (const Vec3& p : src) dst.push_back(Vec3(p.x(), -p.y(), p.z()));  // a mirror image
    const RigidFit fit = fit_rigid(src, dst);
    ASSERT_TRUE(fit.ok);
    EXPECT_NEAR(fit.T.linear().determinant(), 1.0, 1e-9);
    EXPECT_GT(fit.rms, 1e-3);  // a rotation cannot explain a mirror image
  }
}

TEST(FitRigid, RefusesDegenerateInput) {
  EXPECT_FALSE(fit_rigid({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {Vec3(0, 0, 0), Vec3(1, 0, 0)}).ok);
  const std::vector<Vec3> line = {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(3, 3, 3)};
  EXPECT_FALSE(fit_rigid(line, line).ok);
  EXPECT_FALSE(
      fit_rigid({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {Vec3(0, 0, 0), Vec3(1, 0, 0)}).ok);
}

TEST(Rpy, RoundTripsAndFollowsTheExtrinsicXyzConvention) {
  const Vec3 rpy(10, -20, 30);
  const Mat3 R = rotation_from_rpy_deg(rpy);
  EXPECT_LT((rpy_deg(R) - rpy).norm(), 1e-9);
  // Pure yaw of 90 deg turns x into y.
  EXPECT_LT((rotation_from_rpy_deg(Vec3(0, 0, 90)) * Vec3::UnitX() - Vec3::UnitY()).norm(), 1e-12);
  // Pure pitch of 90 deg turns x into -z.
  EXPECT_LT((rotation_from_rpy_deg(Vec3(0, 90, 0)) * Vec3::UnitX() + Vec3::UnitZ()).norm(), 1e-12);
}

TEST(MarkerFrameCorners, AreTopLeftTopRightBottomRightBottomLeft) {
  const auto c = marker_frame_corners(2.0);
  EXPECT_EQ(c[0], Vec3(-1, 1, 0));
  EXPECT_EQ(c[1], Vec3(1, 1, 0));
  EXPECT_EQ(c[2], Vec3(1, -1, 0));
  EXPECT_EQ(c[3], Vec3(-1, -1, 0));
}

}  // namespace
}  // namespace iilfm
