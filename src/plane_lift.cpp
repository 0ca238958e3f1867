#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "iilfm/lift.hpp"

namespace iilfm {

namespace {

// Least-squares plane through points (smallest principal axis of their scatter).
Plane fit_plane(const std::vector<Vec3>& points) {
  Plane plane;
  if (points.size() < 3) return plane;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : points) centre += p;
  centre /= static_cast<double>(points.size());
  Mat3 scatter = Mat3::Zero();
  for (const Vec3& p : points) scatter += (p - centre) * (p - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
  // The two larger spreads must be real: a row of points does not define a plane.
  if (!(eig.eigenvalues()(1) > 1e-12)) return plane;
  plane.normal = eig.eigenvectors().col(0);
  if (plane.normal.dot(centre) > 0) plane.normal = -plane.normal;  // face the sensor
  plane.d = plane.normal.dot(centre);
  double sum_sq = 0;
  for (const Vec3& p : points) sum_sq += std::pow(plane.normal.dot(p) - plane.d, 2);
  plane.rms = std::sqrt(sum_sq / static_cast<double>(points.size()));
  plane.inliers = points.size();
  plane.ok = true;
  return plane;
}

std::vector<Vec3> points_inside(const std::vector<Vec2>& polygon_px, const ProjectedImage& image,
                                const PointCloud& cloud) {
  std::vector<Vec3> points;
  if (polygon_px.size() < 3) return points;
  const ImageGeometry& g = image.geometry;
  std::vector<cv::Point> polygon;
  double min_u = 1e18, max_u = -1e18, min_v = 1e18, max_v = -1e18;
  for (const Vec2& p : polygon_px) {
    if (!p.allFinite()) return points;
    polygon.emplace_back(static_cast<int>(std::lround(p.x())),
                         static_cast<int>(std::lround(p.y())));
    min_u = std::min(min_u, p.x());
    max_u = std::max(max_u, p.x());
    min_v = std::min(min_v, p.y());
    max_v = std::max(max_v, p.y());
  }
  const int c0 = std::max(0, static_cast<int>(std::floor(min_u)));
  const int c1 = std::min(g.width - 1, static_cast<int>(std::ceil(max_u)));
  const int r0 = std::max(0, static_cast<int>(std::floor(min_v)));
  const int r1 = std::min(g.height - 1, static_cast<int>(std::ceil(max_v)));
  if (c0 > c1 || r0 > r1) return points;

  // Rasterise the polygon into a mask over its bounding box.
  cv::Mat inside(r1 - r0 + 1, c1 - c0 + 1, CV_8U, cv::Scalar(0));
  for (cv::Point& p : polygon) p -= cv::Point(c0, r0);
  cv::fillConvexPoly(inside, polygon, cv::Scalar(255));
  for (int r = r0; r <= r1; ++r) {
    const std::uint8_t* in = inside.ptr<std::uint8_t>(r - r0);
    for (int c = c0; c <= c1; ++c) {
      if (!in[c - c0] || !image.observed(c, r)) continue;
      if (image.count.at<std::int32_t>(r, c) == 1) {
        points.push_back(cloud.point(static_cast<std::size_t>(image.index.at<std::int32_t>(r, c))));
      } else {
        points.push_back(pixel_point(image, c, r));
      }
    }
  }
  return points;
}

}  // namespace

Plane fit_marker_plane(const std::vector<Vec2>& polygon_px, const ProjectedImage& image,
                       const PointCloud& cloud, const PlaneFitOptions& options) {
  std::vector<Vec3> points = points_inside(polygon_px, image, cloud);
  if (points.size() < options.min_points) return Plane{};
  Plane plane = fit_plane(points);
  std::vector<Vec3> inliers;
  std::vector<double> residuals;
  for (int it = 0; it < options.iterations && plane.ok; ++it) {
    residuals.clear();
    for (const Vec3& p : points) residuals.push_back(std::abs(plane.normal.dot(p) - plane.d));
    std::vector<double> sorted = residuals;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double robust_sigma = 1.4826 * sorted[sorted.size() / 2];
    const double band = std::max(options.min_inlier_band_m, 3 * robust_sigma);
    inliers.clear();
    for (std::size_t i = 0; i < points.size(); ++i)
      if (residuals[i] <= band) inliers.push_back(points[i]);
    if (inliers.size() < options.min_points || inliers.size() == points.size()) break;
    plane = fit_plane(inliers);
    points.swap(inliers);
  }
  return plane;
}

LiftedCorner lift_on_plane(const Vec2& keypoint_px, const ProjectedImage& image,
                           const Plane& plane) {
  LiftedCorner lifted;
  if (!plane.ok || !keypoint_px.allFinite()) return lifted;
  const Vec3 ray = image.geometry.ray(keypoint_px);
  const double along = plane.normal.dot(ray);
  // Grazing rays (under ~3 deg to the plane) put the corner anywhere along the plane.
  if (std::abs(along) < 0.05) return lifted;
  const double t = plane.d / along;
  if (!(t > 0)) return lifted;
  lifted.point = ray * t;
  const int col = static_cast<int>(std::lround(keypoint_px.x()));
  const int row = static_cast<int>(std::lround(keypoint_px.y()));
  const bool observed = image.geometry.contains_pixel(col, row) && image.observed(col, row);
  lifted.status = observed ? CornerStatus::kObserved : CornerStatus::kInterpolated;
  return lifted;
}

}  // namespace iilfm
