#include "apriltag_render.hpp"

#include "iilfm/apriltag_families.hpp"

namespace iilfm::testing {

cv::Mat render_apriltag(const std::string& tag_family, int id, int* border_width) {
  const AprilTagImage image = iilfm::render_apriltag(tag_family, id);
  if (border_width) *border_width = image.width_at_border;
  return cv::Mat(image.total_width, image.total_width, CV_8U,
                 const_cast<std::uint8_t*>(image.pixels.data()))
      .clone();
}

}  // namespace iilfm::testing
