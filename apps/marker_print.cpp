#include "marker_print.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "iilfm/error.hpp"
#include "iilfm/image_files.hpp"
#include "iilfm/rings_family.hpp"
#include "iilfm/sim/marker_texture.hpp"

namespace iilfm::cli {

namespace {

constexpr double kMetresPerInch = 0.0254;
constexpr int kExtraQuietCells = 1;  // white cells added around the family's own image
constexpr int kMinPixelsPerCell = 2;

void check_request(const MarkerPrintRequest& r) {
  if (!(r.size_m > 0) || !std::isfinite(r.size_m))
    throw InputError("--size must be a positive number of metres");
  if (!(r.dpi > 0) || !std::isfinite(r.dpi)) throw InputError("--dpi must be positive");
}

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

constexpr const char* kRingsPrefix = "rings:";

// The rings family of a "rings:..." name, or nothing for the cell-grid families.
const RingsFamily* rings_family_of(const std::string& family) {
  if (family.rfind(kRingsPrefix, 0) != 0) return nullptr;
  return &find_rings_family(family.substr(std::string(kRingsPrefix).size()));
}

// Caption lines: what the marker is, and what size it must come out at.
std::vector<std::string> caption_lines(const MarkerPrintRequest& r) {
  const char* what = rings_family_of(r.family) ? "outer diameter " : "square ";
  return {r.family + "  id " + std::to_string(r.id),
          what + format("%.4f", r.size_m) + " m at " + format("%g", r.dpi) + " dpi"};
}

// Ring markers are drawn exactly at the print's resolution, not from the simulator's cells: a
// pixel is black when its centre is.
void draw_rings(const RingsFamily& family, int id, const cv::Rect& square, cv::Mat& image) {
  const double radius = 0.5 * square.width;
  const double cx = square.x + radius - 0.5, cy = square.y + radius - 0.5;
  for (int y = square.y; y < square.y + square.height; ++y)
    for (int x = square.x; x < square.x + square.width; ++x)
      if (family.black_at(id, std::hypot(x - cx, y - cy) / radius))
        image.at<std::uint8_t>(y, x) = 0;
}

}  // namespace

std::string marker_caption(const MarkerPrintRequest& request) {
  const auto lines = caption_lines(request);
  return lines[0] + ", " + lines[1];
}

MarkerPrint render_marker_print(const MarkerPrintRequest& request) {
  check_request(request);
  const sim::MarkerTexture cells = sim::render_marker_texture(request.family, request.id);
  const int border = cells.width_at_border;
  const int margin = (cells.total_width - border) / 2 + kExtraQuietCells;  // cells, each side
  const long square_px = std::lround(request.size_m * request.dpi / kMetresPerInch);
  // Ring markers are drawn exactly at the print's resolution: their rings, not the simulator's
  // cells, need the minimum width (rings across the diameter).
  const RingsFamily* rings = rings_family_of(request.family);
  const int units = rings ? 2 * rings->annuli() : border;
  const std::string unit = rings ? "ring" : "cell";
  if (square_px < static_cast<long>(kMinPixelsPerCell) * units) {
    throw InputError(request.family + " at " + format("%g", request.size_m) + " m and " +
                     format("%g", request.dpi) + " dpi gives " + std::to_string(square_px) +
                     " px for " + std::to_string(units) + " " + unit + "s: fewer than " +
                     std::to_string(kMinPixelsPerCell) + " px per " + unit +
                     " (raise --dpi or --size)");
  }
  // Cell k (counted from the square's left edge) spans [edge(k), edge(k + 1)): whole pixels whose
  // widths differ by at most one, so the square is exactly square_px wide.
  auto edge = [&](int k) {
    return static_cast<int>(std::lround(static_cast<double>(k) * square_px / border));
  };
  const int origin = -edge(-margin);
  const int marker_px = edge(border + margin) + origin;

  const std::vector<std::string> lines = caption_lines(request);
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double text_px = std::clamp(square_px / 25.0, 9.0, 60.0);
  const double scale = text_px / cv::getTextSize("Ag", font, 1.0, 1, nullptr).height;
  const int thickness = std::max(1, static_cast<int>(std::lround(text_px / 12)));
  int text_width = 0, line_height = 0;
  for (const std::string& line : lines) {
    int baseline = 0;
    const cv::Size size = cv::getTextSize(line, font, scale, thickness, &baseline);
    text_width = std::max(text_width, size.width);
    line_height = std::max(line_height, size.height + baseline);
  }
  const int gap = static_cast<int>(std::lround(text_px / 2));
  const int width = std::max(marker_px, text_width + 2 * gap);
  const int left = (width - marker_px) / 2;  // the marker is centred above a wider caption
  const int caption_height = static_cast<int>(lines.size()) * (line_height + gap) + gap;

  MarkerPrint print;
  print.image = cv::Mat(marker_px + caption_height, width, CV_8U, cv::Scalar(255));
  print.square =
      cv::Rect(left + origin, origin, static_cast<int>(square_px), static_cast<int>(square_px));
  print.cell_px = static_cast<double>(square_px) / border;
  if (rings) draw_rings(*rings, request.id, print.square, print.image);
  const int first = -(cells.total_width - border) / 2;  // texture cell 0, in square cells
  for (int row = 0; row < cells.total_width && !rings; ++row) {
    for (int col = 0; col < cells.total_width; ++col) {
      if (!cells.is_black(row, col)) continue;
      const int x0 = edge(first + col) + origin, x1 = edge(first + col + 1) + origin;
      const int y0 = edge(first + row) + origin, y1 = edge(first + row + 1) + origin;
      print.image(cv::Rect(left + x0, y0, x1 - x0, y1 - y0)).setTo(0);
    }
  }
  int y = marker_px;
  for (const std::string& line : lines) {
    y += gap + line_height;
    cv::putText(print.image, line, cv::Point(gap, y), font, scale, cv::Scalar(0), thickness,
                cv::LINE_AA);
  }
  return print;
}

std::string render_marker_svg(const MarkerPrintRequest& request) {
  check_request(request);
  const sim::MarkerTexture cells = sim::render_marker_texture(request.family, request.id);
  const double cell_mm = request.size_m * 1000.0 / cells.width_at_border;
  const double pad_mm = kExtraQuietCells * cell_mm;
  const double marker_mm = cells.total_width * cell_mm + 2 * pad_mm;
  const double font_mm = std::clamp(request.size_m * 1000.0 / 25.0, 2.5, 12.0);
  const std::vector<std::string> lines = caption_lines(request);
  const double height_mm = marker_mm + (lines.size() + 0.5) * 1.6 * font_mm;
  // Glyphs are about 0.6 em wide; the page widens for a long caption.
  std::size_t longest = 0;
  for (const std::string& line : lines) longest = std::max(longest, line.size());
  const double width_mm = std::max(marker_mm, 0.6 * font_mm * longest + 2 * font_mm);
  const double left_mm = (width_mm - marker_mm) / 2 + pad_mm;

  std::ostringstream svg;
  svg.precision(10);
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_mm << "mm\" height=\""
      << height_mm << "mm\" viewBox=\"0 0 " << width_mm << " " << height_mm << "\">\n"
      << "<title>" << marker_caption(request) << "</title>\n"
      << "<rect width=\"" << width_mm << "\" height=\"" << height_mm << "\" fill=\"#fff\"/>\n";
  if (const RingsFamily* rings = rings_family_of(request.family)) {
    // One disc per ring, from the outside in, each painted over the previous.
    const double centre_x = left_mm + 0.5 * cells.total_width * cell_mm;
    const double centre_y = pad_mm + 0.5 * cells.total_width * cell_mm;
    for (int k = 0; k < rings->annuli(); ++k) {
      svg << "<circle cx=\"" << centre_x << "\" cy=\"" << centre_y << "\" r=\""
          << 0.5 * request.size_m * 1000.0 * (1 - k * rings->ring_width()) << "\" fill=\""
          << (rings->annulus_black(request.id, k) ? "#000" : "#fff") << "\"/>\n";
    }
  }
  for (int row = 0; row < cells.total_width && !rings_family_of(request.family); ++row) {
    for (int col = 0; col < cells.total_width;) {
      if (!cells.is_black(row, col)) {
        ++col;
        continue;
      }
      int end = col;
      while (end < cells.total_width && cells.is_black(row, end)) ++end;
      svg << "<rect x=\"" << left_mm + col * cell_mm << "\" y=\"" << pad_mm + row * cell_mm
          << "\" width=\"" << (end - col) * cell_mm << "\" height=\"" << cell_mm
          << "\" fill=\"#000\" shape-rendering=\"crispEdges\"/>\n";
      col = end;
    }
  }
  double y = marker_mm;
  for (const std::string& line : lines) {
    y += 1.6 * font_mm;
    svg << "<text x=\"" << font_mm << "\" y=\"" << y << "\" font-family=\"sans-serif\" font-size=\""
        << font_mm << "\">" << line << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

void write_png_with_dpi(const std::string& path, const cv::Mat& image, double dpi) {
  const std::vector<std::uint8_t> png = encode_png(image, dpi);
  if (png.empty()) throw file_error(path, "cannot encode the PNG");
  write_bytes_to_file(path, png, "the PNG");
}

}  // namespace iilfm::cli
