// ChArUco boards through OpenCV's aruco module (contrib, 4.6 API: CharucoBoard for the layout,
// detectMarkers for its markers; the chessboard corners are placed by local homographies).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "iilfm/charuco_boards.hpp"
#include "iilfm/detector.hpp"

namespace iilfm::detail {

// `board` is "DICT_4X4_50:5x7" (dictionary, columns x rows of squares); InputError if malformed.
std::unique_ptr<MarkerDetector> make_charuco_detector(const std::string& board,
                                                      const ArucoOptions& options);

// Where chessboard corner `corner_id` lies in the board's marker frame (centre origin, x right, y
// up as printed), in units of the square edge.
Vec2 charuco_corner_on_board(const CharucoBoardSpec& spec, int corner_id);

// Boards listed by known_families(): any DICT:COLSxROWS works, these are examples.
std::vector<std::string> charuco_example_families();

// One square is the unit: border_width = cells per square, total_width = the printed board's
// larger side in cells.
FamilyLayout charuco_layout(const std::string& board);

}  // namespace iilfm::detail
