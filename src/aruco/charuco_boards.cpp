// ChArUco boards by name: "DICT_...:COLSxROWS".
#include "iilfm/charuco_boards.hpp"

#include <cstdint>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "iilfm/error.hpp"

namespace iilfm {

namespace {
constexpr int kMaxSquares = 40;
}

CharucoBoardSpec parse_charuco_board(const std::string& name) {
  const auto colon = name.rfind(':');
  const std::string example =
      " (expected charuco:DICT_...:COLSxROWS, e.g. charuco:DICT_4X4_50:5x7)";
  if (colon == std::string::npos)
    throw InputError("ChArUco board 'charuco:" + name + "' has no size" + example);
  CharucoBoardSpec spec;
  spec.dictionary = find_aruco_dictionary(name.substr(0, colon));
  if (!spec.dictionary)
    throw InputError("unknown ArUco dictionary '" + name.substr(0, colon) +
                     "' in 'charuco:" + name + "'" + example);
  const std::string size = name.substr(colon + 1);
  char end = 0;
  if (std::sscanf(size.c_str(), "%dx%d%c", &spec.squares_x, &spec.squares_y, &end) != 2 ||
      spec.squares_x < 3 || spec.squares_y < 3 || spec.squares_x > kMaxSquares ||
      spec.squares_y > kMaxSquares)
    throw InputError("ChArUco board size '" + size + "' in 'charuco:" + name +
                     "' must be COLSxROWS with 3 to " + std::to_string(kMaxSquares) +
                     " squares each");
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(spec.dictionary->id);
  spec.marker_bits = dictionary->markerSize;
  if (spec.markers() > dictionary->bytesList.rows)
    throw InputError("ChArUco board 'charuco:" + name + "' needs " +
                     std::to_string(spec.markers()) + " markers, its dictionary has " +
                     std::to_string(dictionary->bytesList.rows));
  return spec;
}

cv::Ptr<cv::aruco::CharucoBoard> make_charuco_board(const CharucoBoardSpec& spec, int board_id,
                                                    const std::string& family) {
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(spec.dictionary->id);
  const int boards = dictionary->bytesList.rows / spec.markers();
  if (board_id < 0 || board_id >= boards)
    throw InputError("board id " + std::to_string(board_id) + " is outside " + family + " (0.." +
                     std::to_string(boards - 1) + ": board k uses marker ids from k * " +
                     std::to_string(spec.markers()) + ")");
  cv::Ptr<cv::aruco::CharucoBoard> board = cv::aruco::CharucoBoard::create(
      spec.squares_x, spec.squares_y, static_cast<float>(spec.square_cells()),
      static_cast<float>(spec.marker_bits + 2), dictionary);
  for (int& id : board->ids) id += board_id * spec.markers();
  return board;
}

cv::Mat draw_charuco_cells(const CharucoBoardSpec& spec, int board_id, const std::string& family,
                           int margin, int px_per_cell) {
  const cv::Ptr<cv::aruco::CharucoBoard> board = make_charuco_board(spec, board_id, family);
  // OpenCV resamples each marker into place; at one pixel per cell that blurs bits (measured: 7 of
  // 17 DICT_6X6_250 markers unreadable), so draw at 8 pixels per cell and read the cell centres.
  constexpr int kOversample = 8;
  const int cols = spec.squares_x * spec.square_cells() + 2 * margin;
  const int rows = spec.squares_y * spec.square_cells() + 2 * margin;
  cv::Mat fine;
  board->draw(cv::Size(cols * kOversample, rows * kOversample), fine, margin * kOversample, 1);
  cv::Mat cells(rows, cols, CV_8U);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      cells.at<std::uint8_t>(r, c) = fine.at<std::uint8_t>(r * kOversample + kOversample / 2,
                                                           c * kOversample + kOversample / 2) < 128
                                         ? 0
                                         : 255;
  if (px_per_cell == 1) return cells;
  cv::Mat scaled;
  cv::resize(cells, scaled, cv::Size(), px_per_cell, px_per_cell, cv::INTER_NEAREST);
  return scaled;
}

}  // namespace iilfm
