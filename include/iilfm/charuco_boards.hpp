// ChArUco boards by name ("DICT_4X4_50:5x7"), shared by the detector back-end, the simulator's
// print and `iilfm marker print`.
#pragma once

#include <opencv2/aruco/charuco.hpp>
#include <string>

#include "iilfm/aruco_dictionaries.hpp"

namespace iilfm {

// A board of squares_x columns by squares_y rows of chessboard squares (OpenCV's layout: the
// top-left square as drawn is black), markers from `dictionary` in the white squares.
struct CharucoBoardSpec {
  const ArucoDictionaryEntry* dictionary = nullptr;
  int squares_x = 0, squares_y = 0;
  int marker_bits = 0;  // the dictionary's markerSize

  // Every square is marker_bits + 4 cells: the marker (its bits and a one-cell black border) with a
  // one-cell white margin inside its white square.
  int square_cells() const { return marker_bits + 4; }
  int markers() const { return squares_x * squares_y / 2; }
  int corners() const { return (squares_x - 1) * (squares_y - 1); }
};

// Parses "DICT_4X4_50:5x7"; InputError naming the problem for unknown dictionaries, malformed or
// too small boards (fewer than 3 squares a side) and boards needing more markers than the
// dictionary has.
CharucoBoardSpec parse_charuco_board(const std::string& name);

// OpenCV's board for board number `board_id`, which uses marker ids board_id * markers() onwards,
// in units of cells (square_cells() per square); InputError when the dictionary runs out of ids.
cv::Ptr<cv::aruco::CharucoBoard> make_charuco_board(const CharucoBoardSpec& spec, int board_id,
                                                    const std::string& family);

// The board as drawn by OpenCV at `px_per_cell` pixels per cell (0 black, 255 white), `margin`
// white cells around it.
cv::Mat draw_charuco_cells(const CharucoBoardSpec& spec, int board_id, const std::string& family,
                           int margin, int px_per_cell = 1);

}  // namespace iilfm
