#include "apriltag_render.hpp"

#include <cstdlib>
#include <stdexcept>

#include "../../src/detectors/apriltag_families.hpp"

namespace iilfm::testing {

cv::Mat render_apriltag(const std::string& tag_family, int id, int* border_width) {
  const auto* entry = detail::find_apriltag_family(tag_family);
  if (!entry) throw std::runtime_error("no family " + tag_family);
  apriltag_family_t* family = entry->create();
  image_u8_t* image = apriltag_to_image(family, id);
  cv::Mat out(image->height, image->width, CV_8U);
  for (int r = 0; r < image->height; ++r)
    for (int c = 0; c < image->width; ++c) out.at<uchar>(r, c) = image->buf[r * image->stride + c];
  if (border_width) *border_width = family->width_at_border;
  // Debian's libapriltag does not export image_u8_destroy; the image is two malloc'd blocks.
  std::free(image->buf);
  std::free(image);
  entry->destroy(family);
  return out;
}

}  // namespace iilfm::testing
