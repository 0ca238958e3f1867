#include "iilfm/pose.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace iilfm {

RigidFit fit_rigid(const std::vector<Vec3>& source, const std::vector<Vec3>& target,
                   const std::vector<double>& weights) {
  RigidFit fit;
  const std::size_t n = source.size();
  if (n < 3 || target.size() != n || (!weights.empty() && weights.size() != n)) return fit;
  auto weight = [&](std::size_t i) { return weights.empty() ? 1.0 : weights[i]; };

  Vec3 mean_s = Vec3::Zero(), mean_t = Vec3::Zero();
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(weight(i) >= 0)) return fit;
    mean_s += weight(i) * source[i];
    mean_t += weight(i) * target[i];
    total += weight(i);
  }
  if (!(total > 0)) return fit;
  mean_s /= total;
  mean_t /= total;

  Mat3 cross = Mat3::Zero();
  double spread = 0;
  for (std::size_t i = 0; i < n; ++i) {
    cross += weight(i) * (target[i] - mean_t) * (source[i] - mean_s).transpose();
    spread += weight(i) * (source[i] - mean_s).squaredNorm();
  }
  Eigen::JacobiSVD<Mat3> svd(cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec3 singular = svd.singularValues();
  // Collinear (or coincident) points leave the rotation about their line undetermined.
  if (spread <= 0 || singular(1) <= 1e-9 * singular(0) || singular(0) <= 0) return fit;

  Mat3 D = Mat3::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;
  const Mat3 R = svd.matrixU() * D * svd.matrixV().transpose();

  fit.T.linear() = R;
  fit.T.translation() = mean_t - R * mean_s;
  double sum_sq = 0;
  for (std::size_t i = 0; i < n; ++i) sum_sq += (fit.T * source[i] - target[i]).squaredNorm();
  fit.rms = std::sqrt(sum_sq / static_cast<double>(n));
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
