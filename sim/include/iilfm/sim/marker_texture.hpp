// The printed image of a marker, rendered once by the family's own generator and looked up per
// beam.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace iilfm::sim {

struct MarkerTexture {
  int total_width = 0;               // image side in cells, white quiet zone included
  int width_at_border = 0;           // cells spanned by the outer black square (marker size)
  std::vector<std::uint8_t> pixels;  // total_width^2, row 0 = top of the printed tag; 0 black

  bool is_black(int row, int col) const { return pixels[row * total_width + col] < 128; }
};

// Renders `id` of a family named "apriltag:<name>" with libapriltag's apriltag_to_image (the
// tagCircle families with white paper outside their circle, as officially printed), or
// "aruco:<DICT_...>" with OpenCV's drawMarker (one-cell black border, as the detector expects)
// inside a one-cell white margin, like apriltag_to_image's tag36h11, or "rings:<name>" rasterised
// finely (width_at_border cells = the outer diameter). InputError for other
// prefixes, unknown families and ids outside the family.
MarkerTexture render_marker_texture(const std::string& family, int id);

// Names of the AprilTag families libapriltag ships, with the "apriltag:" prefix.
std::vector<std::string> apriltag_family_names();

// Names of OpenCV's predefined ArUco dictionaries, with the "aruco:" prefix.
std::vector<std::string> aruco_family_names();

// Names of the concentric-ring families (include/iilfm/rings_family.hpp), with the "rings:" prefix.
std::vector<std::string> rings_family_names();

// Every family the simulator prints: the AprilTag families, the ArUco dictionaries, the rings.
std::vector<std::string> marker_family_names();

}  // namespace iilfm::sim
