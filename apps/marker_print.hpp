// Printable marker images (`iilfm marker print`): the family's own generator scaled so that the
// marker's square is exactly the requested size at the requested resolution.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace iilfm::cli {

struct MarkerPrintRequest {
  std::string family;  // "apriltag:tag36h11", "aruco:DICT_4X4_50", ...
  int id = 0;
  double size_m = 0;  // edge of the square whose corners the detector reports
  double dpi = 300;
};

struct MarkerPrint {
  cv::Mat image;       // 8-bit grey: black ink on white paper, the caption below the marker
  cv::Rect square;     // the reported square (FamilyLayout::border_width cells) in pixels
  double cell_px = 0;  // mean cell width in pixels
};

// The caption written on the margin: family, id, size and resolution.
std::string marker_caption(const MarkerPrintRequest& request);

// InputError for unknown families, ids outside the family, a size or DPI that is not positive, and
// prints with fewer than 2 pixels per cell.
MarkerPrint render_marker_print(const MarkerPrintRequest& request);

// A vector print at the same size: one SVG rectangle per run of black cells, sizes in millimetres.
std::string render_marker_svg(const MarkerPrintRequest& request);

// Writes a PNG that carries its resolution (a pHYs chunk), so printing programs print it at size.
void write_png_with_dpi(const std::string& path, const cv::Mat& image, double dpi);

}  // namespace iilfm::cli
