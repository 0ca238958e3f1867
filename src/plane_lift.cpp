#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "iilfm/lift.hpp"
#include "iilfm/square_pixels.hpp"

namespace iilfm {

namespace {

// Least-squares plane through points (smallest principal axis of their scatter), without its
// uncertainty (add_plane_uncertainty): the robust fit's intermediate planes do not need it.
Plane fit_plane(const std::vector<Vec3>& points) {
  Plane plane;
  if (points.size() < 3) return plane;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : points) centre += p;
  centre /= static_cast<double>(points.size());
  // The six distinct entries of the scatter matrix, one pass.
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (const Vec3& p : points) {
    const double x = p.x() - centre.x(), y = p.y() - centre.y(), z = p.z() - centre.z();
    xx += x * x;
    xy += x * y;
    xz += x * z;
    yy += y * y;
    yz += y * z;
    zz += z * z;
  }
  Mat3 scatter;
  scatter << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(scatter);
  // The two larger spreads must be real: a row of points does not define a plane.
  if (!(eig.eigenvalues()(1) > 1e-12)) return plane;
  plane.normal = eig.eigenvectors().col(0);
  if (plane.normal.dot(centre) > 0) plane.normal = -plane.normal;  // face the sensor
  plane.d = plane.normal.dot(centre);
  plane.centre = centre;
  plane.axis1 = eig.eigenvectors().col(1);
  plane.axis2 = eig.eigenvectors().col(2);
  plane.inliers = points.size();
  plane.ok = true;
  return plane;
}

// The fitted plane's RMS residual and uncertainty, from the residuals themselves
// (heteroscedasticity-consistent, White's sandwich): the points are not equally noisy (a pixel's
// point may be the mean of several returns, and a rosette is densest at its centre), so the far,
// sparse points that fix the slope must count with their own scatter. Scaled by n / (n - 3) for
// the 3 fitted parameters.
void add_plane_uncertainty(const std::vector<Vec3>& points, Plane& plane) {
  if (!plane.ok) return;
  const double n = static_cast<double>(points.size());
  double sum_sq = 0, s1 = 0, s2 = 0, h1 = 0, h2 = 0;
  for (const Vec3& p : points) {
    const double r = plane.normal.dot(p) - plane.d;
    const double r2 = r * r;
    const Vec3 q = p - plane.centre;
    const double x1 = q.dot(plane.axis1), x2 = q.dot(plane.axis2);
    sum_sq += r2;
    s1 += x1 * x1;
    s2 += x2 * x2;
    h1 += x1 * x1 * r2;
    h2 += x2 * x2 * r2;
  }
  plane.rms = std::sqrt(sum_sq / n);
  const double dof_scale = points.size() > 3 ? n / (n - 3) : 0;
  plane.offset_variance = dof_scale * sum_sq / (n * n);
  plane.slope_variance = Eigen::Vector2d(dof_scale * h1 / (s1 * s1), dof_scale * h2 / (s2 * s2));
}

std::vector<cv::Point> rounded(const std::vector<Vec2>& polygon_px, cv::Point origin) {
  std::vector<cv::Point> out;
  for (const Vec2& p : polygon_px)
    out.emplace_back(static_cast<int>(std::lround(p.x())) - origin.x,
                     static_cast<int>(std::lround(p.y())) - origin.y);
  return out;
}

// Polygons are drawn in a frame uniform in angle, so a marker keeps its shape and a surround
// scaled about it covers the same angles on every side, also when image rows follow rings.
struct PolygonFrame {
  ImageGeometry uniform;     // uniform rows, the image's columns
  std::vector<double> v_of;  // uniform row coordinate of each image row
};

PolygonFrame polygon_frame(const ImageGeometry& g) {
  PolygonFrame frame;
  frame.uniform = g.ring_rows() ? square_pixel_geometry(g) : g;
  frame.v_of.resize(static_cast<std::size_t>(std::max(g.height, 0)));
  for (int r = 0; r < g.height; ++r)
    frame.v_of[static_cast<std::size_t>(r)] =
        g.ring_rows() ? frame.uniform.v_of_elevation(g.elevation_of_v(r)) : r;
  return frame;
}

// Points of the observed pixels inside `polygon` but not inside `excluded` (may be empty); both
// in the frame's uniform coordinates.
std::vector<Vec3> points_inside(const std::vector<Vec2>& polygon, const ProjectedImage& image,
                                const PointView& cloud, const PolygonFrame& frame,
                                const std::vector<Vec2>& excluded = {}) {
  std::vector<Vec3> points;
  if (polygon.size() < 3) return points;
  const ImageGeometry& g = image.geometry;
  double min_u = 1e18, max_u = -1e18, min_v = 1e18, max_v = -1e18;
  for (const Vec2& p : polygon) {
    if (!p.allFinite()) return points;
    min_u = std::min(min_u, p.x());
    max_u = std::max(max_u, p.x());
    min_v = std::min(min_v, p.y());
    max_v = std::max(max_v, p.y());
  }
  const int c0 = std::max(0, static_cast<int>(std::floor(min_u)));
  const int c1 = std::min(g.width - 1, static_cast<int>(std::ceil(max_u)));
  const int v0 = static_cast<int>(std::floor(min_v)), v1 = static_cast<int>(std::ceil(max_v));
  if (c0 > c1 || v0 > v1) return points;

  // Rasterise the polygon into a mask over its bounding box.
  cv::Mat inside(v1 - v0 + 1, c1 - c0 + 1, CV_8U, cv::Scalar(0));
  cv::fillConvexPoly(inside, rounded(polygon, cv::Point(c0, v0)), cv::Scalar(255));
  if (excluded.size() >= 3)
    cv::fillConvexPoly(inside, rounded(excluded, cv::Point(c0, v0)), cv::Scalar(0));
  for (int r = 0; r < g.height; ++r) {
    const int v = static_cast<int>(std::lround(frame.v_of[static_cast<std::size_t>(r)]));
    if (v < v0 || v > v1) continue;
    const std::uint8_t* in = inside.ptr<std::uint8_t>(v - v0);
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

namespace {

// Least squares, then refits without points farther than max(min band, 3 robust sigmas).
// Leaves the final inliers in `points`.
Plane robust_plane(std::vector<Vec3>& points, const PlaneFitOptions& options, double* band_out) {
  Plane plane = fit_plane(points);
  thread_local std::vector<Vec3> inliers;  // reused from marker to marker
  thread_local std::vector<double> residuals, sorted;
  double band = options.min_inlier_band_m;
  for (int it = 0; it < options.iterations && plane.ok; ++it) {
    residuals.clear();
    for (const Vec3& p : points) residuals.push_back(std::abs(plane.normal.dot(p) - plane.d));
    sorted.assign(residuals.begin(), residuals.end());
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    band = std::max(options.min_inlier_band_m, 3 * 1.4826 * sorted[sorted.size() / 2]);
    inliers.clear();
    for (std::size_t i = 0; i < points.size(); ++i)
      if (residuals[i] <= band) inliers.push_back(points[i]);
    if (inliers.size() < options.min_points || inliers.size() == points.size()) break;
    plane = fit_plane(inliers);
    points.swap(inliers);
  }
  add_plane_uncertainty(points, plane);
  if (band_out) *band_out = band;
  return plane;
}

std::vector<Vec2> scaled_about_centre(const std::vector<Vec2>& polygon, double scale) {
  Vec2 centre = Vec2::Zero();
  for (const Vec2& p : polygon) centre += p / static_cast<double>(polygon.size());
  std::vector<Vec2> out;
  for (const Vec2& p : polygon) out.push_back(centre + scale * (p - centre));
  return out;
}

}  // namespace

Plane fit_marker_plane(const std::vector<Vec2>& polygon_px, const ProjectedImage& image,
                       const PointView& cloud, const PlaneFitOptions& options) {
  const PolygonFrame frame = polygon_frame(image.geometry);
  std::vector<Vec2> polygon;
  for (const Vec2& px : polygon_px) polygon.push_back(map_pixel(px, image.geometry, frame.uniform));
  std::vector<Vec3> marker_points = points_inside(polygon, image, cloud, frame);
  if (marker_points.size() < options.min_points) return Plane{};
  double band = 0;
  Plane plane = robust_plane(marker_points, options, &band);
  if (!plane.ok) return plane;

  // A printed sheet is flush with what it hangs on: when the surround is coplanar with the marker,
  // its points pin the normal down far better (more points, longer lever). Largest ring first.
  for (double scale : options.surround_scales) {
    std::vector<Vec3> ring =
        points_inside(scaled_about_centre(polygon, scale), image, cloud, frame, polygon);
    if (ring.size() < marker_points.size() / 2) continue;
    std::size_t coplanar = 0;
    for (const Vec3& p : ring) coplanar += std::abs(plane.normal.dot(p) - plane.d) <= band;
    if (coplanar < options.min_coplanar_fraction * static_cast<double>(ring.size())) continue;
    // Coplanar: take the ring's points within 4 of its own robust sigmas. The marker's band is
    // too narrow for the ring when the ring's pixels average fewer returns (a rosette is densest
    // at its centre): cutting the ring's tails about the marker's own, tilted plane pulls the
    // wide fit towards the marker's tilt (measured: twice the tilt error of an untruncated fit).
    std::vector<double> offsets;
    for (const Vec3& p : ring) offsets.push_back(std::abs(plane.normal.dot(p) - plane.d));
    std::nth_element(offsets.begin(), offsets.begin() + offsets.size() / 2, offsets.end());
    const double ring_band = std::max(band, 4 * 1.4826 * offsets[offsets.size() / 2]);
    std::vector<Vec3> all = marker_points;
    for (const Vec3& p : ring)
      if (std::abs(plane.normal.dot(p) - plane.d) <= ring_band) all.push_back(p);
    Plane wide = robust_plane(all, options, nullptr);
    if (!wide.ok) continue;
    // The normal from the wide fit; the offset from the marker's own points, so a sheet standing a
    // little proud of its wall (a board, a thick print) keeps its own depth.
    double offset = 0;
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : marker_points) {
      offset += wide.normal.dot(p);
      centre += p;
    }
    const double n_marker = static_cast<double>(marker_points.size());
    wide.d = offset / n_marker;
    wide.surround_scale = scale;
    // The offset is the marker points' mean (the variance of a mean of their residuals), the
    // slopes the wide fit's, about the marker's centroid.
    double sum_sq = 0;
    for (const Vec3& p : marker_points) sum_sq += std::pow(wide.normal.dot(p) - wide.d, 2);
    wide.offset_variance = sum_sq / (n_marker * std::max(1.0, n_marker - 1));
    wide.centre = centre / n_marker;
    return wide;
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
