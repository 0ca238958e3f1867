#include "iilfm/lift.hpp"

#include <cmath>

namespace iilfm {

const char* to_string(CornerStatus status) {
  switch (status) {
    case CornerStatus::kObserved:
      return "observed";
    case CornerStatus::kInterpolated:
      return "interpolated";
    case CornerStatus::kUnrecoverable:
      return "unrecoverable";
  }
  return "unrecoverable";
}

Vec3 pixel_point(const ProjectedImage& image, int col, int row) {
  col = image.geometry.wrap_column(col);
  return image.geometry.ray(col, row) * static_cast<double>(image.range.at<float>(row, col));
}

namespace {

bool observed_at(const ProjectedImage& image, int col, int row) {
  col = image.geometry.wrap_column(col);  // a marker across the seam of a full circle
  return image.geometry.contains_pixel(col, row) && image.observed(col, row);
}

Vec3 bisector_point(const Vec3& a, const Vec3& b) {
  const double ra = a.norm(), rb = b.norm();
  return (rb * a + ra * b) / (ra + rb);
}

}  // namespace

LiftedCorner lift_paper(const Vec2& keypoint_px, const ProjectedImage& image,
                        const LiftOptions& options) {
  LiftedCorner lifted;
  if (!keypoint_px.allFinite()) return lifted;
  const int col = static_cast<int>(std::lround(keypoint_px.x()));
  const int row = static_cast<int>(std::lround(keypoint_px.y()));
  if (observed_at(image, col, row)) {
    lifted.point = image.geometry.ray(keypoint_px) *
                   static_cast<double>(image.range.at<float>(row, image.geometry.wrap_column(col)));
    lifted.status = CornerStatus::kObserved;
    return lifted;
  }
  // Same column first (the paper's rule), then the same row.
  for (const auto& [dc, dr] : {std::pair{0, 1}, std::pair{1, 0}}) {
    for (int d = 1; d <= options.max_pair_distance_px; ++d) {
      const int c_a = col - d * dc, r_a = row - d * dr, c_b = col + d * dc, r_b = row + d * dr;
      if (observed_at(image, c_a, r_a) && observed_at(image, c_b, r_b)) {
        lifted.point = bisector_point(pixel_point(image, c_a, r_a), pixel_point(image, c_b, r_b));
        lifted.status = CornerStatus::kInterpolated;
        return lifted;
      }
    }
  }
  return lifted;
}

}  // namespace iilfm
