#include "iilfm/pose.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "rigid_fit_sums.hpp"

namespace iilfm {

namespace detail {

RigidFitSums rigid_fit_sums(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                            const std::vector<double>& weights) {
  RigidFitSums sums;
  const std::size_t n = source.size();
  if (n < 3 || target.size() != n || (!weights.empty() && weights.size() != n)) return sums;
  auto weight = [&](std::size_t i) { return weights.empty() ? 1.0 : weights[i]; };
  for (std::size_t i = 0; i < n; ++i) {
    if (!(weight(i) >= 0)) return sums;
    sums.mean_source += weight(i) * source[i];
    sums.mean_target += weight(i) * target[i];
    sums.total += weight(i);
  }
  if (!(sums.total > 0)) return sums;
  sums.mean_source /= sums.total;
  sums.mean_target /= sums.total;
  for (std::size_t i = 0; i < n; ++i) {
    sums.cross +=
        weight(i) * (target[i] - sums.mean_target) * (source[i] - sums.mean_source).transpose();
    sums.spread += weight(i) * (source[i] - sums.mean_source).squaredNorm();
  }
  sums.ok = true;
  return sums;
}

bool rigid_transform_of(const RigidFitSums& sums, Isometry3& T) {
  if (!sums.ok) return false;
  Eigen::JacobiSVD<Mat3> svd(sums.cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec3 singular = svd.singularValues();
  // Collinear (or coincident) points leave the rotation about their line undetermined.
  if (sums.spread <= 0 || singular(1) <= 1e-9 * singular(0) || singular(0) <= 0) return false;
  Mat3 D = Mat3::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;
  const Mat3 R = svd.matrixU() * D * svd.matrixV().transpose();
  T = Isometry3::Identity();
  T.linear() = R;
  T.translation() = sums.mean_target - R * sums.mean_source;
  return true;
}

}  // namespace detail

RigidFit fit_rigid(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                   const std::vector<double>& weights) {
  RigidFit fit;
  if (!detail::rigid_transform_of(detail::rigid_fit_sums(source, target, weights), fit.T))
    return fit;  // T stays the identity
  double sum_sq = 0;
  for (std::size_t i = 0; i < source.size(); ++i)
    sum_sq += (fit.T * source[i] - target[i]).squaredNorm();
  fit.rms = std::sqrt(sum_sq / static_cast<double>(source.size()));
  fit.ok = true;
  return fit;
}

std::array<Vec3, 4> marker_frame_corners(double size) {
  const double h = size / 2;
  return {Vec3(-h, h, 0), Vec3(h, h, 0), Vec3(h, -h, 0), Vec3(-h, -h, 0)};
}

Vec3 rpy_deg(const Mat3& R) {
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double roll = std::atan2(R(2, 1), R(2, 2));
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  return Vec3(roll, pitch, yaw) * (180.0 / M_PI);
}

Mat3 rotation_from_rpy_deg(const Vec3& rpy) {
  const Vec3 r = rpy * (M_PI / 180.0);
  return (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

}  // namespace iilfm
