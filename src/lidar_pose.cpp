#include "iilfm/lidar_pose.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "iilfm/pose.hpp"

namespace iilfm {

namespace {

// RMS distance of a marker's lifted corners from where T_lidar_world puts its map corners.
double marker_residual(const MarkerCorrespondence& m, const Isometry3& T_lidar_world) {
  double sum = 0;
  for (std::size_t k = 0; k < m.world.size(); ++k)
    sum += (T_lidar_world * m.world[k] - m.lidar[k]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(m.world.size()));
}

// RMS distance of all corners of `markers` from where T_lidar_world puts them.
double rms_residual(const std::vector<MarkerCorrespondence>& markers,
                    const Isometry3& T_lidar_world) {
  double sum = 0;
  std::size_t n = 0;
  for (const MarkerCorrespondence& m : markers) {
    for (std::size_t k = 0; k < m.world.size(); ++k, ++n)
      sum += (T_lidar_world * m.world[k] - m.lidar[k]).squaredNorm();
  }
  return n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0;
}

double tolerance(const MarkerCorrespondence& m, const LidarPoseOptions& options) {
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : m.lidar) centre += p / static_cast<double>(m.lidar.size());
  return options.max_marker_residual_m + options.max_marker_residual_per_metre * centre.norm() +
         m.shape_rms_m;
}

// The used markers' corners stacked, with their joint covariance (block diagonal over markers;
// left empty when a marker's is unknown) and, when asked, inverse-variance weights.
struct Stacked {
  std::vector<Vec3> world, lidar;
  std::vector<double> weights;
  Eigen::MatrixXd covariance;
};

Stacked stack(const std::vector<MarkerCorrespondence>& markers, const std::vector<bool>& use,
              bool weighted) {
  Stacked s;
  bool known = true;
  for (std::size_t i = 0; i < markers.size(); ++i) {
    if (!use[i]) continue;
    const MarkerCorrespondence& m = markers[i];
    s.world.insert(s.world.end(), m.world.begin(), m.world.end());
    s.lidar.insert(s.lidar.end(), m.lidar.begin(), m.lidar.end());
    known = known && m.lidar_covariance.rows() == static_cast<Eigen::Index>(3 * m.lidar.size());
  }
  if (!known) return s;
  const Eigen::Index n = static_cast<Eigen::Index>(3 * s.lidar.size());
  s.covariance = Eigen::MatrixXd::Zero(n, n);
  Eigen::Index at = 0;
  for (std::size_t i = 0; i < markers.size(); ++i) {
    if (!use[i]) continue;
    const Eigen::MatrixXd& c = markers[i].lidar_covariance;
    s.covariance.block(at, at, c.rows(), c.cols()) = c;
    at += c.rows();
  }
  if (weighted) {
    for (Eigen::Index k = 0; k < n / 3; ++k) {
      const double variance = s.covariance.block<3, 3>(3 * k, 3 * k).trace();
      s.weights.push_back(variance > 0 ? 1 / variance : 1.0);
    }
  }
  return s;
}

RigidFit fit_markers(const std::vector<MarkerCorrespondence>& markers, const std::vector<bool>& use,
                     bool weighted = false) {
  const Stacked s = stack(markers, use, weighted);
  return fit_rigid(s.world, s.lidar, s.weights);
}

// Without known corner covariances: every coordinate's noise from the fit's residual, over the
// 3n - 6 degrees of freedom left.
Eigen::MatrixXd residual_covariance(const std::vector<Vec3>& world, const std::vector<Vec3>& lidar,
                                    const Isometry3& T_lidar_world) {
  const std::size_t n = world.size();
  double sum_sq = 0;
  for (std::size_t k = 0; k < n; ++k) sum_sq += (T_lidar_world * world[k] - lidar[k]).squaredNorm();
  const double dof = std::max(1.0, 3.0 * static_cast<double>(n) - 6);
  return Eigen::MatrixXd::Identity(static_cast<Eigen::Index>(3 * n),
                                   static_cast<Eigen::Index>(3 * n)) *
         (sum_sq / dof);
}

std::vector<bool> consistent_with(const std::vector<MarkerCorrespondence>& markers,
                                  const Isometry3& T_lidar_world, const LidarPoseOptions& options,
                                  double* total_residual = nullptr) {
  std::vector<bool> inlier(markers.size());
  double total = 0;
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const double residual = marker_residual(markers[i], T_lidar_world);
    inlier[i] = residual <= tolerance(markers[i], options);
    if (inlier[i]) total += residual;
  }
  if (total_residual) *total_residual = total;
  return inlier;
}

std::string mm(double metres) {
  std::ostringstream s;
  s.precision(3);
  s << metres * 1000 << " mm";
  return s.str();
}

}  // namespace

LidarPoseResult estimate_lidar_pose(const std::vector<MarkerCorrespondence>& markers,
                                    const LidarPoseOptions& options) {
  LidarPoseResult result;
  std::size_t corners = 0;
  for (const MarkerCorrespondence& m : markers) corners += m.world.size();
  const std::size_t needed = std::max<std::size_t>(3, options.min_corners);
  if (markers.empty()) {
    result.failure = "no mapped marker detected";
    return result;
  }
  result.rejected = true;  // from here on, every failure is a refusal of what was found
  if (corners < needed) {
    result.failure = "only " + std::to_string(corners) +
                     " mapped corners could be lifted to 3-D (need " + std::to_string(needed) + ")";
    return result;
  }

  std::vector<bool> use(markers.size(), true);
  if (markers.size() >= 3) {
    // Every single marker's pose is a hypothesis; keep the one most markers agree with.
    std::size_t best_count = 0;
    double best_residual = 0;
    for (const MarkerCorrespondence& m : markers) {
      const RigidFit own = fit_rigid(m.world, m.lidar);
      if (!own.ok) continue;
      double residual = 0;
      const std::vector<bool> inliers = consistent_with(markers, own.T, options, &residual);
      const std::size_t count =
          static_cast<std::size_t>(std::count(inliers.begin(), inliers.end(), true));
      if (count > best_count || (count == best_count && residual < best_residual)) {
        best_count = count;
        best_residual = residual;
        use = inliers;
      }
    }
    if (best_count < 2) use.assign(markers.size(), true);  // no two markers agree: judge below
  }

  RigidFit fit = fit_markers(markers, use);
  if (fit.ok && markers.size() >= 3) {
    // Re-judge every marker against the pose of all agreeing markers, once.
    const std::vector<bool> refined = consistent_with(markers, fit.T, options);
    if (std::count(refined.begin(), refined.end(), true) >= 2 && refined != use) {
      use = refined;
      fit = fit_markers(markers, use);
    }
  }
  if (fit.ok && options.weight_corners) {
    const RigidFit weighted = fit_markers(markers, use, true);
    if (weighted.ok) fit = weighted;
  }
  if (!fit.ok) {
    result.failure = "mapped corners are collinear";
    return result;
  }

  LidarPose& pose = result.pose;
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const double residual = marker_residual(markers[i], fit.T);
    if (use[i] && residual <= tolerance(markers[i], options)) {
      pose.markers_used.push_back(markers[i].key);
      pose.corners_used += markers[i].world.size();
    } else if (use[i]) {
      // Too few markers to outvote this one, and it does not fit: the pose cannot be trusted.
      result.failure = "markers disagree with the map: " + markers[i].key + " is " + mm(residual) +
                       " off (tolerance " + mm(tolerance(markers[i], options)) + ")";
      return result;
    } else {
      pose.markers_rejected.push_back({markers[i].key, residual});
    }
  }
  if (pose.corners_used < needed) {
    result.failure = "only " + std::to_string(pose.corners_used) +
                     " corners in the markers that agree (need " + std::to_string(needed) + ")";
    return result;
  }
  if (!(fit.rms <= options.max_rms_m)) {
    result.failure = "corner RMS residual " + mm(fit.rms) + " exceeds the bound " +
                     mm(options.max_rms_m) + " (--max-pose-rms)";
    return result;
  }
  pose.T_world_lidar = fit.T.inverse();
  pose.rms = fit.rms;
  Stacked s = stack(markers, use, options.weight_corners);
  if (s.covariance.size() == 0) s.covariance = residual_covariance(s.world, s.lidar, fit.T);
  pose.covariance = rigid_fit_covariance(s.world, s.lidar, s.weights, s.covariance, true);
  if (options.refine == PoseRefine::kPoints) {
    std::vector<MarkerCorrespondence> used;
    for (std::size_t i = 0; i < markers.size(); ++i)
      if (use[i]) used.push_back(markers[i]);
    PoseRefinement refined = refine_lidar_pose(used, pose.T_world_lidar, pose.covariance);
    if (refined.ok) {
      pose.T_world_lidar = refined.T_world_lidar;
      pose.covariance = refined.covariance;
      pose.rms = rms_residual(used, pose.T_world_lidar.inverse());
    }
    pose.planes_used = std::move(refined.planes_used);
    pose.planes_rejected = std::move(refined.planes_rejected);
  }
  result.rejected = false;
  result.ok = true;
  return result;
}

}  // namespace iilfm
