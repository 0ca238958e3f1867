#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

#include "iilfm/error.hpp"
#include "iilfm/image_files.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/report.hpp"
#include "iilfm/square_pixels.hpp"

namespace iilfm {

cv::Mat draw_overlay(const FrameResult& result) {
  const cv::Mat& gray = result.preprocessed.gray;
  if (gray.empty()) return cv::Mat(1, 1, CV_8UC3, cv::Scalar(0, 0, 0));
  // Drawn on the detector's image; corners are in the projected image's coordinates.
  const ImageGeometry& g = result.preprocessed.geometry;
  const ImageGeometry& projected = result.image.geometry;

  // Square pixels in angle, and at least ~1200 px wide (capped so huge images stay small files).
  const double aspect = g.res_v / g.res_h;
  double sx = std::clamp(1200.0 / gray.cols, 1.0, 8.0);
  double sy = sx * aspect;
  const double max_side = 4000.0;
  const double shrink = std::min({1.0, max_side / (gray.cols * sx), max_side / (gray.rows * sy)});
  sx *= shrink;
  sy *= shrink;

  cv::Mat color;
  cv::cvtColor(gray, color, cv::COLOR_GRAY2BGR);
  color.setTo(cv::Scalar(40, 90, 40), result.preprocessed.valid == 0);
  cv::Mat canvas;
  cv::resize(color, canvas, cv::Size(), sx, sy, cv::INTER_NEAREST);

  // Continuous image coordinates (centres at integers) to canvas coordinates.
  auto to_canvas = [&](const Vec2& image_px) {
    const Vec2 px = map_pixel(image_px, projected, g);
    return cv::Point2d((px.x() + 0.5) * sx - 0.5, (px.y() + 0.5) * sy - 0.5);
  };
  const cv::Scalar corner_colors[4] = {{0, 0, 255}, {0, 200, 0}, {255, 80, 0}, {0, 220, 255}};
  const int thickness = std::max(1, static_cast<int>(std::lround(std::min(sx, sy) / 2)));
  for (const MarkerResult& m : result.markers) {
    const auto& c = m.detection.corners_px;
    const std::size_t n = c.size();
    const std::vector<Vec2> outline = keypoint_outline(m.detection);  // a board: its hull
    for (std::size_t k = 0; k < outline.size(); ++k) {
      cv::line(canvas, to_canvas(outline[k]), to_canvas(outline[(k + 1) % outline.size()]),
               cv::Scalar(0, 160, 255), thickness, cv::LINE_AA);
    }
    for (std::size_t k = 0; k < n; ++k) {
      const cv::Point2d p = to_canvas(c[k]);
      cv::circle(canvas, p, 3 * thickness + 1, corner_colors[k % 4], cv::FILLED, cv::LINE_AA);
      cv::putText(canvas, std::to_string(k + 1), p + cv::Point2d(4, -4), cv::FONT_HERSHEY_SIMPLEX,
                  0.4 * thickness + 0.2, corner_colors[k % 4], 1, cv::LINE_AA);
    }
    Vec2 centre = Vec2::Zero();
    for (const Vec2& px : c) centre += px / static_cast<double>(n);
    const std::string label = "#" + std::to_string(m.detection.id);
    // Label size from the top edge, or the outline's width for a ring marker (one keypoint).
    double width = 0;
    if (n >= 2) {
      width = (to_canvas(c[1]) - to_canvas(c[0])).x;
    } else if (!outline.empty()) {
      double left = 1e300, right = -1e300;
      for (const Vec2& px : outline) {
        left = std::min(left, to_canvas(px).x);
        right = std::max(right, to_canvas(px).x);
      }
      width = right - left;
    }
    const double size = std::clamp(width / 60.0, 0.4, 1.5);
    int baseline = 0;
    const cv::Size text = cv::getTextSize(label, cv::FONT_HERSHEY_SIMPLEX, size, 2, &baseline);
    const cv::Point2d at = to_canvas(centre) - cv::Point2d(text.width / 2.0, -text.height / 2.0);
    cv::putText(canvas, label, at, cv::FONT_HERSHEY_SIMPLEX, size, cv::Scalar(255, 255, 255), 4,
                cv::LINE_AA);
    cv::putText(canvas, label, at, cv::FONT_HERSHEY_SIMPLEX, size, cv::Scalar(0, 0, 220), 2,
                cv::LINE_AA);
  }
  return canvas;
}

namespace {
// True for a .jpg/.jpeg path, false for .png; InputError for anything else.
bool overlay_as_jpeg(const std::string& path) {
  const std::string extension = io::lower_extension(path);
  const bool jpeg = extension == ".jpg" || extension == ".jpeg";
  if (!jpeg && extension != ".png")
    throw file_error(path, "the image is written as PNG or JPEG: use a .png or .jpg path");
  return jpeg;
}
}  // namespace

void check_overlay_path(const std::string& path) { overlay_as_jpeg(path); }

void write_overlay(const std::string& path, const FrameResult& result) {
  const bool jpeg = overlay_as_jpeg(path);
  const cv::Mat overlay = draw_overlay(result);
  const std::vector<std::uint8_t> bytes = jpeg ? encode_jpeg(overlay, 95) : encode_png(overlay);
  if (bytes.empty()) throw file_error(path, "cannot encode the image");
  write_bytes_to_file(path, bytes, jpeg ? "the JPEG" : "the PNG");
}

}  // namespace iilfm
