// Marker images straight from each family's own generator (libapriltag's apriltag_to_image,
// OpenCV's drawMarker), so the simulated print is exactly what the detector expects.
#include "iilfm/sim/marker_texture.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/aruco.hpp>
#include <opencv2/core.hpp>

#include "iilfm/apriltag_families.hpp"
#include "iilfm/aruco_dictionaries.hpp"
#include "iilfm/charuco_boards.hpp"
#include "iilfm/error.hpp"
#include "iilfm/rings_family.hpp"

namespace iilfm::sim {
namespace {

constexpr const char* kAprilTagPrefix = "apriltag:";
constexpr const char* kArucoPrefix = "aruco:";
constexpr const char* kCharucoPrefix = "charuco:";
constexpr const char* kRingsPrefix = "rings:";
// Texture cells across one ring of a rings marker: the staircase of the rasterised circles stays
// under an eighth of a ring width.
constexpr int kCellsPerRing = 8;

bool has_prefix(const std::string& text, const std::string& prefix) {
  return text.compare(0, prefix.size(), prefix) == 0;
}

[[noreturn]] void unknown_family(const std::string& family) {
  std::string known;
  for (const std::string& n : marker_family_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("the simulator cannot print marker family '" + family + "' (known: " + known +
                   ")");
}

// apriltag_to_image leaves every cell that is not a bit or the white border black, the corners of
// a circle tag included; the official circle prints have no ink there. Cells whose centre lies
// outside the circle inscribed in the image are paper (white), as printed.
void clear_outside_circle(MarkerTexture& texture) {
  const double radius = 0.5 * texture.total_width;
  for (int row = 0; row < texture.total_width; ++row)
    for (int col = 0; col < texture.total_width; ++col) {
      const double dx = col + 0.5 - radius, dy = row + 0.5 - radius;
      if (dx * dx + dy * dy > radius * radius)
        texture.pixels[static_cast<std::size_t>(row * texture.total_width + col)] = 255;
    }
}

MarkerTexture apriltag_texture(const std::string& name, int id) {
  AprilTagImage image = render_apriltag(name, id);
  MarkerTexture texture;
  texture.total_width = image.total_width;
  texture.width_at_border = image.width_at_border;
  texture.pixels = std::move(image.pixels);
  if (name.rfind("tagCircle", 0) == 0) clear_outside_circle(texture);
  return texture;
}

// drawMarker at one pixel per cell: the data bits inside a one-cell black border; a one-cell white
// margin around it stands for the paper the marker is printed on.
MarkerTexture aruco_texture(const ArucoDictionaryEntry& entry, const std::string& family, int id) {
  const cv::Ptr<cv::aruco::Dictionary> dictionary = cv::aruco::getPredefinedDictionary(entry.id);
  if (id < 0 || id >= dictionary->bytesList.rows) {
    throw InputError("marker id " + std::to_string(id) + " is outside " + family + " (0.." +
                     std::to_string(dictionary->bytesList.rows - 1) + ")");
  }
  const int border = dictionary->markerSize + 2;
  cv::Mat marker;
  dictionary->drawMarker(id, border, marker, 1);
  cv::Mat sheet;
  cv::copyMakeBorder(marker, sheet, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(255));
  MarkerTexture texture;
  texture.total_width = border + 2;
  texture.width_at_border = border;
  texture.pixels.assign(sheet.begin<std::uint8_t>(), sheet.end<std::uint8_t>());
  return texture;
}

// OpenCV's drawing of the board at one pixel per cell with one white cell around it, centred on a
// square sheet (the texture is square): the sheet's centre is the board's centre, and one
// chessboard square is the marker size.
MarkerTexture charuco_texture(const std::string& family, int id) {
  const CharucoBoardSpec spec =
      parse_charuco_board(family.substr(std::string(kCharucoPrefix).size()));
  // Texture cells are half cells when the board's sides differ by an odd number of cells, so
  // the padding to a square sheet splits evenly.
  const int scale = (spec.squares_x - spec.squares_y) * spec.square_cells() % 2 != 0 ? 2 : 1;
  const cv::Mat board = draw_charuco_cells(spec, id, family, 1, scale);
  const int side = std::max(board.cols, board.rows);
  cv::Mat sheet;
  cv::copyMakeBorder(board, sheet, (side - board.rows) / 2, (side - board.rows) / 2,
                     (side - board.cols) / 2, (side - board.cols) / 2, cv::BORDER_CONSTANT,
                     cv::Scalar(255));
  MarkerTexture texture;
  texture.total_width = side;
  texture.width_at_border = spec.square_cells() * scale;
  for (auto it = sheet.begin<std::uint8_t>(); it != sheet.end<std::uint8_t>(); ++it)
    texture.pixels.push_back(*it < 128 ? 0 : 255);
  return texture;
}

// The rings rasterised at kCellsPerRing cells per ring: a cell is black when its centre is. The
// marker size is the outer diameter, the sheet adds the white quiet zone around it.
MarkerTexture rings_texture(const std::string& name, int id) {
  const RingsFamily& family = find_rings_family(name);
  check_rings_id(family, id);
  const int radius = kCellsPerRing * family.annuli();
  const int quiet = static_cast<int>(std::lround(kRingsQuietZone * radius));
  MarkerTexture texture;
  texture.width_at_border = 2 * radius;
  texture.total_width = 2 * (radius + quiet);
  const double half = 0.5 * texture.total_width;
  for (int row = 0; row < texture.total_width; ++row)
    for (int col = 0; col < texture.total_width; ++col) {
      const double r = std::hypot(col + 0.5 - half, row + 0.5 - half) / radius;
      texture.pixels.push_back(family.black_at(id, r) ? 0 : 255);
    }
  return texture;
}

}  // namespace

std::vector<std::string> rings_family_names() {
  std::vector<std::string> names;
  for (const RingsFamily& family : rings_families())
    names.push_back(std::string(kRingsPrefix) + family.name);
  return names;
}

std::vector<std::string> apriltag_family_names() {
  std::vector<std::string> names;
  for (const AprilTagFamilyEntry& entry : apriltag_families())
    names.push_back(std::string(kAprilTagPrefix) + entry.name);
  return names;
}

std::vector<std::string> aruco_family_names() {
  std::vector<std::string> names;
  for (const ArucoDictionaryEntry& entry : aruco_dictionaries())
    names.push_back(std::string(kArucoPrefix) + entry.name);
  return names;
}

std::vector<std::string> marker_family_names() {
  std::vector<std::string> names = apriltag_family_names();
  for (const std::string& name : aruco_family_names()) names.push_back(name);
  for (const std::string& name : rings_family_names()) names.push_back(name);
  return names;
}

MarkerTexture render_marker_texture(const std::string& family, int id) {
  if (has_prefix(family, kAprilTagPrefix)) {
    const std::string name = family.substr(std::string(kAprilTagPrefix).size());
    if (find_apriltag_family(name)) return apriltag_texture(name, id);
  } else if (has_prefix(family, kArucoPrefix)) {
    const ArucoDictionaryEntry* entry =
        find_aruco_dictionary(family.substr(std::string(kArucoPrefix).size()));
    if (entry) return aruco_texture(*entry, family, id);
  } else if (has_prefix(family, kCharucoPrefix)) {
    return charuco_texture(family, id);
  } else if (has_prefix(family, kRingsPrefix)) {
    return rings_texture(family.substr(std::string(kRingsPrefix).size()), id);
  }
  unknown_family(family);
}

}  // namespace iilfm::sim
