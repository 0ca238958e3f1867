// Test helper: the official rendering of an AprilTag (libapriltag's apriltag_to_image) as a
// cv::Mat.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace iilfm::testing {

// The tag image, one pixel per cell (total_width square), row 0 = top of the printed tag.
cv::Mat render_apriltag(const std::string& tag_family, int id, int* border_width = nullptr);

}  // namespace iilfm::testing
