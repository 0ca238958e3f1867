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

double tolerance(const MarkerCorrespondence& m, const LidarPoseOptions& options) {
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : m.lidar) centre += p / static_cast<double>(m.lidar.size());
  return options.max_marker_residual_m + options.max_marker_residual_per_metre * centre.norm();
}

RigidFit fit_markers(const std::vector<MarkerCorrespondence>& markers,
                     const std::vector<bool>& use) {
  std::vector<Vec3> world, lidar;
  for (std::size_t i = 0; i < markers.size(); ++i) {
    if (!use[i]) continue;
    world.insert(world.end(), markers[i].world.begin(), markers[i].world.end());
    lidar.insert(lidar.end(), markers[i].lidar.begin(), markers[i].lidar.end());
  }
  return fit_rigid(world, lidar);
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
  pose.T_world_lidar = fit.T.inverse();
  pose.rms = fit.rms;
  result.ok = true;
  return result;
}

}  // namespace iilfm
