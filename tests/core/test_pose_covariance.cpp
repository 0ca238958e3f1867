#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "iilfm/lidar_pose.hpp"
#include "iilfm/pose.hpp"
#include "iilfm/pose_covariance.hpp"

namespace iilfm {
namespace {

// A 17 cm square marker 3 m ahead, turned a little, as the fit's target.
struct Square {
  std::vector<Vec3> model, corners;
  Isometry3 T = Isometry3::Identity();
};

Square make_square() {
  Square s;
  s.T.linear() = rotation_from_rpy_deg(Vec3(-80, 5, -95));
  s.T.translation() = Vec3(3.0, 0.4, -0.2);
  for (const Vec3& c : marker_frame_corners(0.172)) {
    s.model.push_back(c);
    s.corners.push_back(s.T * c);
  }
  return s;
}

// Empirical covariance of the fitted pose (convention of pose_covariance.hpp) over noisy draws of
// the corners with covariance L L^T.
Mat6 monte_carlo(const Square& s, const Eigen::MatrixXd& L, bool inverse, int draws) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  const Isometry3 truth = inverse ? s.T.inverse() : s.T;
  Mat6 sum = Mat6::Zero();
  for (int i = 0; i < draws; ++i) {
    Eigen::VectorXd z(L.cols());
    for (Eigen::Index k = 0; k < z.size(); ++k) z(k) = normal(rng);
    const Eigen::VectorXd d = L * z;
    std::vector<Vec3> noisy = s.corners;
    for (std::size_t k = 0; k < noisy.size(); ++k) noisy[k] += d.segment<3>(3 * k);
    const RigidFit fit = fit_rigid(s.model, noisy);
    const Isometry3 T = inverse ? fit.T.inverse() : fit.T;
    Eigen::Matrix<double, 6, 1> e;
    const Eigen::AngleAxisd turn(truth.linear().transpose() * T.linear());
    e.head<3>() = turn.angle() * turn.axis();
    e.tail<3>() = T.translation() - truth.translation();
    sum += e * e.transpose();
  }
  return sum / draws;
}

void expect_diagonal_near(const Mat6& predicted, const Mat6& observed) {
  for (int i = 0; i < 6; ++i) {
    // 4000 draws: the sample variance is within about 5 % (2.2 sigma); allow 10 %.
    EXPECT_NEAR(std::sqrt(observed(i, i)) / std::sqrt(predicted(i, i)), 1.0, 0.1)
        << "axis " << i << ": predicted " << predicted(i, i) << ", observed " << observed(i, i);
  }
}

TEST(PoseCovariance, MatchesMonteCarloForIsotropicCornerNoise) {
  const Square s = make_square();
  const double sigma = 0.002;
  const Eigen::MatrixXd C = Eigen::MatrixXd::Identity(12, 12) * sigma * sigma;
  const Eigen::MatrixXd L = Eigen::MatrixXd::Identity(12, 12) * sigma;
  for (bool inverse : {false, true}) {
    const Mat6 predicted = rigid_fit_covariance(s.model, s.corners, {}, C, inverse);
    expect_diagonal_near(predicted, monte_carlo(s, L, inverse, 4000));
  }
  // Translation of the square's centre: the mean of 4 corners, sigma / 2 per axis.
  const Mat6 own = rigid_fit_covariance(s.model, s.corners, {}, C, false);
  EXPECT_NEAR(translation_std(own).x(), sigma / 2, 1e-6);
}

TEST(PoseCovariance, MatchesMonteCarloForCornersOnAnUncertainPlane) {
  Square s = make_square();
  Plane plane;
  plane.normal = -(s.T.linear() * Vec3::UnitZ());  // the marker's face, towards the sensor
  if (plane.normal.dot(s.T.translation()) > 0) plane.normal = -plane.normal;
  plane.d = plane.normal.dot(s.T.translation());
  plane.ok = true;
  plane.centre = s.T.translation();
  plane.axis1 = s.T.linear() * Vec3::UnitX();
  plane.axis2 = s.T.linear() * Vec3::UnitY();
  plane.offset_variance = 1e-6;                        // 1 mm along the normal
  plane.slope_variance = Eigen::Vector2d(4e-4, 1e-4);  // 1.1 and 0.6 deg of tilt
  const Eigen::MatrixXd C = plane_corner_covariance(s.corners, plane, 0.001);
  // The plane moves the corners along their rays: correlated, rank-deficient, so draw through
  // the eigen decomposition.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(C);
  const Eigen::MatrixXd L =
      eig.eigenvectors() * eig.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal();
  const Mat6 predicted = rigid_fit_covariance(s.model, s.corners, {}, C, false);
  expect_diagonal_near(predicted, monte_carlo(s, L, false, 4000));
  // The tilt about the marker's x axis is the plane's slope along its y axis (and the reverse).
  EXPECT_NEAR(std::sqrt(predicted(0, 0)), 0.01, 0.001);
  EXPECT_NEAR(std::sqrt(predicted(1, 1)), 0.02, 0.002);
}

TEST(PoseCovariance, InPlaneSigmaIgnoresAShrink) {
  const Square s = make_square();
  std::vector<Vec3> shrunk;
  // 3.4 mm narrower and 1.7 mm lower: a footprint taller than wide shrinks the square unevenly.
  for (const Vec3& c : s.model) shrunk.push_back(s.T * Vec3(0.98 * c.x(), 0.99 * c.y(), 0));
  EXPECT_LT(affine_residual_sq(s.model, shrunk, s.T), 1e-18);
  std::vector<Vec3> bent = shrunk;
  bent[0] += s.T.linear() * Vec3(0.001, 0, 0);  // one corner 1 mm off along the marker's x
  // An affine map fits any 3 of 4 points; the 4th's misfit, shared by the 4 corners' residuals
  // as +-d/4 each: 4 (1 mm / 4)^2.
  EXPECT_NEAR(affine_residual_sq(s.model, bent, s.T), 0.25e-6, 1e-9);
  // 4 corners: 8 in-plane residuals, 6 fitted. A perfect fit still claims the prior's share.
  EXPECT_NEAR(in_plane_sigma(2e-6, 4, 0.0, 0), 1e-3, 1e-12);
  EXPECT_NEAR(in_plane_sigma(0.0, 4, 0.001, 2), std::sqrt(2e-6 / 4), 1e-12);
}

// Image corners of `s` seen 100 pixels per metre of the marker, turned by `angle_deg` in the image.
std::vector<Vec2> image_corners(const Square& s, double angle_deg) {
  const Eigen::Rotation2Dd turn(angle_deg * M_PI / 180);
  std::vector<Vec2> px;
  for (const Vec3& c : s.model) px.push_back(Vec2(300, 200) + turn * (100 * c.head<2>()));
  return px;
}

TEST(PoseCovariance, AnEdgeOffsetIsSharedByItsTwoCorners) {
  const Square s = make_square();
  constexpr double kSigmaPx = 0.3, kMetresPerPixel = 0.01;
  const Eigen::MatrixXd C = edge_offset_covariance(s.model, image_corners(s, 0), s.T, kSigmaPx);
  ASSERT_EQ(C.rows(), 12);
  // In the marker frame: corner 0 (top left) moves with the top edge along y and with the left
  // edge along x, each by 0.3 pixels; never along the normal.
  const auto block = [&](int k, int l) {
    return Mat3(s.T.linear().transpose() * C.block<3, 3>(3 * k, 3 * l) * s.T.linear());
  };
  const double var = std::pow(kSigmaPx * kMetresPerPixel, 2);
  EXPECT_NEAR(block(0, 0)(0, 0), var, 1e-12);
  EXPECT_NEAR(block(0, 0)(1, 1), var, 1e-12);
  EXPECT_NEAR(block(0, 0)(2, 2), 0, 1e-15);
  // Corners 0 and 1 share the top edge (the marker's y) but not a side edge.
  EXPECT_NEAR(block(0, 1)(1, 1), var, 1e-12);
  EXPECT_NEAR(block(0, 1)(0, 0), 0, 1e-15);
  // Opposite corners share nothing.
  EXPECT_NEAR(block(0, 2).norm(), 0, 1e-15);
  // The centre moves by the mean of two opposite edges: half their variance per axis.
  Eigen::MatrixXd mean_x = Eigen::MatrixXd::Zero(1, 12);
  for (int k = 0; k < 4; ++k) mean_x.block<1, 3>(0, 3 * k) = s.T.linear().col(0).transpose() / 4;
  EXPECT_NEAR((mean_x * C * mean_x.transpose())(0, 0), var / 2, 1e-12);
}

TEST(PoseCovariance, ASlantedEdgeAveragesItsQuantisation) {
  const Square s = make_square();
  const Eigen::MatrixXd along_grid = edge_offset_covariance(s.model, image_corners(s, 0), s.T, 0.3);
  const Eigen::MatrixXd slanted = edge_offset_covariance(s.model, image_corners(s, 30), s.T, 0.3);
  // A 17.2 pixel edge turned 30 degrees crosses 8.6 pixel phases: variance / 9.6.
  EXPECT_NEAR(slanted.trace() / along_grid.trace(), 1 / 9.6, 1e-6);
  EXPECT_EQ(edge_offset_covariance(s.model, {}, s.T, 0.3).size(), 0);
}

TEST(PoseCovariance, RpyStdFollowsTheRotationStd) {
  Mat6 C = Mat6::Zero();
  C(2, 2) = std::pow(0.01, 2);  // yaw about the pose's own z axis, 0.57 deg
  const Isometry3 level = Isometry3::Identity();
  const Vec3 sd = rpy_std_deg(level, C);
  EXPECT_NEAR(sd.z(), 0.01 * 180 / M_PI, 1e-6);
  EXPECT_NEAR(sd.x(), 0, 1e-9);
  EXPECT_NEAR(sd.y(), 0, 1e-9);
}

TEST(FitRigidWeighted, ZeroWeightIgnoresAPoint) {
  const Square s = make_square();
  std::vector<Vec3> model = s.model, corners = s.corners;
  model.push_back(Vec3(0.3, 0.3, 0));
  corners.push_back(s.T * model.back() + Vec3(0.05, -0.04, 0.1));  // far off
  const RigidFit plain = fit_rigid(model, corners);
  const RigidFit weighted = fit_rigid(model, corners, {1, 1, 1, 1, 0});
  ASSERT_TRUE(weighted.ok);
  EXPECT_GT((plain.T.translation() - s.T.translation()).norm(), 1e-3);
  EXPECT_LT((weighted.T.translation() - s.T.translation()).norm(), 1e-9);
  EXPECT_FALSE(fit_rigid(model, corners, {1, 1, 1}).ok);  // wrong count
  EXPECT_FALSE(fit_rigid(model, corners, {1, 1, 1, 1, -1}).ok);
}

// rigid_fit_covariance updates the centre fit's sums for each perturbed target point; the same
// Jacobian refitted from scratch (fit_rigid on the moved points) must give the same covariance,
// weighted and not, for the pose and for its inverse.
TEST(PoseCovariance, WeightedFitMatchesAJacobianRefittedFromScratch) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1, 1);
  const Square s = make_square();
  std::vector<Vec3> source, target;
  std::vector<double> weights;
  for (int k = 0; k < 12; ++k) {
    source.push_back(Vec3(uniform(rng), uniform(rng), 0.1 * uniform(rng)));
    target.push_back(s.T * source.back() + 0.002 * Vec3(uniform(rng), uniform(rng), uniform(rng)));
    weights.push_back(1.5 + uniform(rng));
  }
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(36, 36);
  for (Eigen::Index i = 0; i < 36; ++i)
    for (Eigen::Index j = 0; j <= i; ++j) L(i, j) = 0.001 * uniform(rng);
  const Eigen::MatrixXd target_cov = L * L.transpose();
  for (const bool weighted : {false, true}) {
    for (const bool inverse : {false, true}) {
      const std::vector<double> w = weighted ? weights : std::vector<double>{};
      const auto pose_of = [&](const std::vector<Vec3>& t) {
        const RigidFit fit = fit_rigid(source, t, w);
        return inverse ? fit.T.inverse() : fit.T;
      };
      const Isometry3 centre = pose_of(target);
      const auto difference = [&](const Isometry3& T) {
        Eigen::Matrix<double, 6, 1> x;
        const Eigen::AngleAxisd turn(centre.linear().transpose() * T.linear());
        x.head<3>() = turn.angle() * turn.axis();
        x.tail<3>() = T.translation() - centre.translation();
        return x;
      };
      Eigen::MatrixXd J(6, 36);
      constexpr double kStep = 1e-5;
      for (int col = 0; col < 36; ++col) {
        std::vector<Vec3> plus = target, minus = target;
        plus[col / 3](col % 3) += kStep;
        minus[col / 3](col % 3) -= kStep;
        J.col(col) = (difference(pose_of(plus)) - difference(pose_of(minus))) / (2 * kStep);
      }
      const Mat6 expected = J * target_cov * J.transpose();
      const Mat6 C = rigid_fit_covariance(source, target, w, target_cov, inverse);
      EXPECT_LT((C - expected).norm(), 1e-6 * expected.norm())
          << "weighted " << weighted << ", inverse " << inverse;
      EXPECT_GT(C.norm(), 0);
    }
  }
}

// One marker 4 m ahead with its corners as given.
MarkerCorrespondence marker(const std::vector<Vec3>& lidar) {
  MarkerCorrespondence m;
  m.key = "apriltag:tag36h11/0";
  for (const Vec3& c : marker_frame_corners(0.172)) {
    const Vec3 world(4, -c.x(), c.y());
    m.world.push_back(world);
  }
  m.lidar = lidar;
  return m;
}

TEST(LidarPoseHonesty, RefusesAPoseWithAResidualOverTheBound) {
  MarkerCorrespondence m = marker({});
  m.lidar = m.world;
  m.lidar[0] += Vec3(0, 0.05, 0);  // a corner 5 cm off: about 2 cm RMS
  LidarPoseOptions options;
  options.max_rms_m = 0.01;
  const LidarPoseResult r = estimate_lidar_pose({m}, options);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.rejected);
  EXPECT_NE(r.failure.find("exceeds the bound 10 mm"), std::string::npos) << r.failure;
  options.max_rms_m = 0.05;
  EXPECT_TRUE(estimate_lidar_pose({m}, options).ok);
}

TEST(LidarPoseHonesty, NeedsTheConfiguredNumberOfCorners) {
  MarkerCorrespondence m = marker({});
  m.lidar = m.world;
  m.world.pop_back();
  m.lidar.pop_back();  // three corners
  LidarPoseResult r = estimate_lidar_pose({m});
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.rejected);
  LidarPoseOptions three;
  three.min_corners = 3;
  r = estimate_lidar_pose({m}, three);
  ASSERT_TRUE(r.ok) << r.failure;
  // Exact corners without a covariance: the residual (zero) stands in, so the pose claims zero.
  EXPECT_LT(r.pose.covariance.norm(), 1e-12);
  EXPECT_FALSE(estimate_lidar_pose({}).rejected);  // nothing found: not a refusal
}

TEST(LidarPoseHonesty, CovarianceComesFromTheCornersCovariance) {
  MarkerCorrespondence m = marker({});
  m.lidar = m.world;  // LiDAR at the world origin
  m.lidar_covariance = Eigen::MatrixXd::Identity(12, 12) * 1e-6;
  const LidarPoseResult r = estimate_lidar_pose({m});
  ASSERT_TRUE(r.ok) << r.failure;
  // Rotation about the LiDAR's z: in-plane for the marker at x = 4, from 4 corners 0.122 m from
  // its centre: sigma = 1 mm / sqrt(4 * 0.122^2) = 4.1 mrad.
  EXPECT_NEAR(std::sqrt(r.pose.covariance(0, 0)), 0.001 / std::sqrt(4 * 2 * 0.086 * 0.086), 1e-4);
  // Position along x is the marker's distance: 0.5 mm from 4 corners.
  EXPECT_NEAR(translation_std(r.pose.covariance).x(), 0.0005, 1e-5);
}

}  // namespace
}  // namespace iilfm
