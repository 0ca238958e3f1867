#include "iilfm/square_shape.hpp"

#include <Eigen/Geometry>

#include "iilfm/pose.hpp"

namespace iilfm {

SquareShape nearest_square(const std::array<Vec3, 4>& corners) {
  const std::array<Vec3, 4> unit = marker_frame_corners(1.0);
  Eigen::Matrix<double, 3, 4> from, to;
  for (int k = 0; k < 4; ++k) {
    from.col(k) = unit[static_cast<std::size_t>(k)];
    to.col(k) = corners[static_cast<std::size_t>(k)];
  }
  // Umeyama's similarity: rotation, translation and scale; its scale is the square's edge.
  const Eigen::Matrix4d T = Eigen::umeyama(from, to, true);
  const Eigen::Matrix<double, 3, 4> fitted =
      (T.topLeftCorner<3, 3>() * from).colwise() + T.topRightCorner<3, 1>();
  SquareShape shape;
  shape.side_m = T.topLeftCorner<3, 3>().col(0).norm();
  shape.rms_m = std::sqrt((fitted - to).colwise().squaredNorm().mean());
  shape.centre = to.rowwise().mean();
  return shape;
}

}  // namespace iilfm
