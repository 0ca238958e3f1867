#include "iilfm/pose_covariance.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>

#include "iilfm/pose.hpp"
#include "rigid_fit_sums.hpp"

namespace iilfm {

namespace {

Vec3 rotation_log(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// The perturbation (right rotation, translation difference) taking `reference` to `T`.
Eigen::Matrix<double, 6, 1> pose_difference(const Isometry3& reference, const Isometry3& T) {
  Eigen::Matrix<double, 6, 1> x;
  x.head<3>() = rotation_log(reference.linear().transpose() * T.linear());
  x.tail<3>() = T.translation() - reference.translation();
  return x;
}

double wrap_deg(double a) {
  while (a > 180) a -= 360;
  while (a <= -180) a += 360;
  return a;
}

}  // namespace

Eigen::MatrixXd plane_corner_covariance(const std::vector<Vec3>& corners, const Plane& plane,
                                        double in_plane_sigma) {
  const std::size_t n = corners.size();
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  const Mat3 in_plane = Mat3::Identity() - plane.normal * plane.normal.transpose();
  // A plane moved by h along its normal moves the corner on ray r by r h / (n.r).
  std::vector<Vec3> along(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 ray = corners[k].normalized();
    const double cos_incidence = plane.normal.dot(ray);
    along[k] = std::abs(cos_incidence) > 1e-3 ? Vec3(ray / cos_incidence) : Vec3::Zero();
  }
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t l = 0; l < n; ++l) {
      C.block<3, 3>(3 * k, 3 * l) =
          plane.offset_covariance(corners[k], corners[l]) * along[k] * along[l].transpose();
    }
    C.block<3, 3>(3 * k, 3 * k) += in_plane_sigma * in_plane_sigma * in_plane;
  }
  return C;
}

Eigen::MatrixXd edge_offset_covariance(const std::vector<Vec3>& model,
                                       const std::vector<Vec2>& corners_px, const Isometry3& T,
                                       double sigma_px) {
  const std::size_t n = model.size();
  if (n < 3 || corners_px.size() != n) return {};
  // Affine map from the marker plane (metres) to the image (pixels), least squares.
  Eigen::MatrixXd M(static_cast<Eigen::Index>(n), 3);
  Eigen::MatrixXd Y(static_cast<Eigen::Index>(n), 2);
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    M.row(row) << model[i].x(), model[i].y(), 1.0;
    Y.row(row) = corners_px[i].transpose();
  }
  const Eigen::MatrixXd coefficients = M.colPivHouseholderQr().solve(Y);
  const Eigen::Matrix2d A = coefficients.topRows<2>().transpose();  // pixels per metre
  Eigen::MatrixXd C =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * n), static_cast<Eigen::Index>(3 * n));
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t b = (a + 1) % n;
    const Vec2 edge = corners_px[b] - corners_px[a];
    if (edge.norm() < 1e-9) continue;
    const Vec2 image_normal = Vec2(-edge.y(), edge.x()).normalized();
    // An image line moved by 1 pixel along its normal moves by 1 / |A^T n| metres in the plane,
    // along A^T n.
    const Vec2 plane_normal = A.transpose() * image_normal;
    if (plane_normal.norm() < 1e-12) continue;
    const double metres_per_pixel = 1.0 / plane_normal.norm();
    const double phases = 1.0 + std::min(std::abs(edge.x()), std::abs(edge.y()));
    const double sigma = sigma_px * metres_per_pixel / std::sqrt(phases);
    const Vec3 shift = T.linear() * Vec3(plane_normal.x(), plane_normal.y(), 0).normalized();
    const Mat3 block = sigma * sigma * shift * shift.transpose();
    for (const std::size_t k : {a, b})
      for (const std::size_t l : {a, b})
        C.block<3, 3>(static_cast<Eigen::Index>(3 * k), static_cast<Eigen::Index>(3 * l)) += block;
  }
  return C;
}

double affine_residual_sq(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                          const Isometry3& T) {
  const std::size_t n = std::min(source.size(), target.size());
  if (n < 3) return 0;
  // In the model's plane: target (x, y) = A source (x, y) + b, least squares per coordinate.
  Eigen::MatrixXd M(static_cast<Eigen::Index>(n), 3);
  Eigen::MatrixXd Y(static_cast<Eigen::Index>(n), 2);
  const Isometry3 inverse = T.inverse();
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = static_cast<Eigen::Index>(i);
    M.row(row) << source[i].x(), source[i].y(), 1.0;
    Y.row(row) = (inverse * target[i]).head<2>().transpose();
  }
  const Eigen::MatrixXd coefficients = M.colPivHouseholderQr().solve(Y);
  return (M * coefficients - Y).squaredNorm();
}

double in_plane_sigma(double residual_sq, std::size_t corners, double prior_sigma,
                      double prior_dof) {
  const double dof = std::max(0.0, 2 * static_cast<double>(corners) - 6);
  if (dof + prior_dof <= 0) return prior_sigma;
  return std::sqrt((residual_sq + prior_dof * prior_sigma * prior_sigma) / (dof + prior_dof));
}

Mat6 rigid_fit_covariance(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                          const std::vector<double>& weights, const Eigen::MatrixXd& target_cov,
                          bool inverse) {
  const std::size_t n = target.size();
  Mat6 C = Mat6::Zero();
  if (target_cov.rows() != static_cast<Eigen::Index>(3 * n) ||
      target_cov.cols() != target_cov.rows())
    return C;
  // Each perturbed fit updates the sums of the centre one (detail::RigidFitSums: a move of one
  // target point changes its mean and one rank-one term of the cross sum) instead of summing every
  // pair again: 6n fits of n pairs each were most of a 39-marker grid's pose stage.
  const detail::RigidFitSums sums = detail::rigid_fit_sums(source, target, weights);
  const auto solve = [&](const detail::RigidFitSums& s, Isometry3& out) {
    if (!detail::rigid_transform_of(s, out)) return false;
    if (inverse) out = out.inverse();
    return true;
  };
  Isometry3 centre;
  if (!solve(sums, centre)) return C;
  // Steps far above rounding, far below any corner error.
  constexpr double kStep = 1e-5;
  Eigen::MatrixXd J(6, 3 * n);
  for (std::size_t k = 0; k < n; ++k) {
    const double w = weights.empty() ? 1.0 : weights[k];
    const Vec3 lever = source[k] - sums.mean_source;
    for (int a = 0; a < 3; ++a) {
      const auto moved = [&](double step) {
        detail::RigidFitSums s = sums;
        s.mean_target(a) += w * step / sums.total;
        s.cross.row(a) += w * step * lever.transpose();
        return s;
      };
      Isometry3 plus, minus;
      if (!solve(moved(kStep), plus) || !solve(moved(-kStep), minus)) return Mat6::Zero();
      J.col(static_cast<Eigen::Index>(3 * k) + a) =
          (pose_difference(centre, plus) - pose_difference(centre, minus)) / (2 * kStep);
    }
  }
  C = J * target_cov * J.transpose();
  return (C + C.transpose()) / 2;
}

Vec3 translation_std(const Mat6& C) { return C.diagonal().tail<3>().cwiseMax(0).cwiseSqrt(); }

Vec3 rpy_std_deg(const Isometry3& T, const Mat6& C) {
  // d rpy / d (right rotation), by central differences.
  constexpr double kStep = 1e-6;
  Mat3 J;
  for (int a = 0; a < 3; ++a) {
    const Vec3 plus =
        rpy_deg(T.linear() * Eigen::AngleAxisd(kStep, Vec3::Unit(a)).toRotationMatrix());
    const Vec3 minus =
        rpy_deg(T.linear() * Eigen::AngleAxisd(-kStep, Vec3::Unit(a)).toRotationMatrix());
    for (int r = 0; r < 3; ++r) J(r, a) = wrap_deg(plus(r) - minus(r)) / (2 * kStep);
  }
  const Mat3 cov = J * C.topLeftCorner<3, 3>() * J.transpose();
  return cov.diagonal().cwiseMax(0).cwiseSqrt();
}

}  // namespace iilfm
