// Lifting detected 2-D keypoints back to 3-D points in the LiDAR frame (paper Sec. III-D).
#pragma once

#include <string>
#include <vector>

#include "iilfm/projection.hpp"

namespace iilfm {

enum class CornerStatus {
  kObserved,       // the keypoint's pixel holds points: its range along the keypoint's ray
  kInterpolated,   // unobserved: from a symmetric pair of observed pixels (angle-bisector rule)
  kUnrecoverable,  // no observed pixel pair to interpolate from; `point` is meaningless
};

const char* to_string(CornerStatus status);

struct LiftedCorner {
  Vec3 point = Vec3::Zero();
  CornerStatus status = CornerStatus::kUnrecoverable;
  bool valid() const { return status != CornerStatus::kUnrecoverable; }
};

struct LiftOptions {
  // How far (pixels) from the keypoint the symmetric pair may lie. The paper's Remark 2 assumes the
  // pair is still on the marker plane, so this stays small.
  int max_pair_distance_px = 6;
};

// The paper's rule. An observed keypoint pixel gives the point at the pixel's range along the ray
// through the sub-pixel keypoint. An unobserved one is interpolated from the nearest observed pair
// symmetric about it in the same column (then, if none, in the same row): with the two points p_a,
// p_b at ranges r_a, r_b, the ray bisecting them meets the segment at
//   p = (r_b * p_a + r_a * p_b) / (r_a + r_b)         (angle-bisector theorem).
// The paper prints the two weights swapped (its M1 multiplies p_d by mu / (1 + mu)); this is the
// geometrically correct form, checked against a plane in the tests.
LiftedCorner lift_paper(const Vec2& keypoint_px, const ProjectedImage& image,
                        const LiftOptions& options = {});

// The 3-D point of an observed pixel: its range along the ray through the pixel centre.
Vec3 pixel_point(const ProjectedImage& image, int col, int row);

// A plane n.x = d in the LiDAR frame (|n| = 1, n facing the sensor).
struct Plane {
  Vec3 normal = Vec3::UnitX();
  double d = 0;
  double rms = 0;             // of the inliers, metres
  std::size_t inliers = 0;    // points used in the final fit
  double surround_scale = 1;  // > 1: the normal came from the coplanar surround this many times
                              // the marker's size
  bool ok = false;
  // Uncertainty: near `centre` the fitted plane's offset along the normal at x is
  //   h(x) = a + b1 (x - centre).axis1 + b2 (x - centre).axis2,
  // with (a, b1, b2) zero-mean, independent, of variances `offset_variance` (m^2) and
  // `slope_variance` (per axis), from the inliers' residual variance and their scatter.
  Vec3 centre = Vec3::Zero();
  Vec3 axis1 = Vec3::UnitY(), axis2 = Vec3::UnitZ();
  double offset_variance = 0;
  Eigen::Vector2d slope_variance = Eigen::Vector2d::Zero();
  // Covariance of h(a) and h(b): how much two points of the plane move together along the normal.
  double offset_covariance(const Vec3& a, const Vec3& b) const {
    const Vec3 da = a - centre, db = b - centre;
    return offset_variance + slope_variance(0) * da.dot(axis1) * db.dot(axis1) +
           slope_variance(1) * da.dot(axis2) * db.dot(axis2);
  }
};

struct PlaneFitOptions {
  std::size_t min_points = 8;
  double min_inlier_band_m = 0.01;  // inlier band is max(this, 3 robust sigmas)
  int iterations = 3;
  // Surrounds (the detected quad scaled about its centre) tried for a coplanar extension, largest
  // first, and the share of their points that must lie on the marker's plane (or, when the
  // marker's own plane is uncertain, on the surround's own plane, with the marker's points).
  std::vector<double> surround_scales = {3.0, 2.0};
  double min_coplanar_fraction = 0.9;
  // Threads gathering the points of a large surround (parts of at least 32k pixels): the same
  // points, so the same plane, for any count. The pipeline gives a frame's single marker its
  // lift threads (PipelineOptions::lift_threads).
  int threads = 1;
};

// Fits the marker's plane robustly to the observed pixels inside the detected polygon, then, when
// the surround is coplanar with it, takes the normal from marker and surround together. A surround
// off that plane is still taken when it is planar and the marker lies on it: its points on the
// surround's plane and its own plane's tilt from it within that tilt's uncertainty (a marker
// crossed by few scan lines). A pixel
// holding one point contributes that point; a pixel holding several contributes its mean range
// along the pixel-centre ray, which is where a locally planar surface crosses that ray.
Plane fit_marker_plane(const std::vector<Vec2>& polygon_px, const ProjectedImage& image,
                       const PointView& cloud, const PlaneFitOptions& options = {});

// Where the ray through a sub-pixel keypoint meets the plane. Status: kObserved when the
// keypoint's pixel holds points, kInterpolated when not, kUnrecoverable when the plane is not
// usable or the ray runs (nearly) parallel to it.
LiftedCorner lift_on_plane(const Vec2& keypoint_px, const ProjectedImage& image,
                           const Plane& plane);

}  // namespace iilfm
