// ChArUco back-end (`charuco:DICT_...:COLSxROWS`): a board is one marker whose keypoints are the
// chessboard corners, placed from the board's detected ArUco markers.
#include "charuco_detector.hpp"

#include <algorithm>
#include <map>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/imgproc.hpp>

#include "aruco_detector.hpp"
#include "iilfm/charuco_boards.hpp"
#include "iilfm/error.hpp"

namespace iilfm::detail {

namespace {

// Fewer corners than this cannot give a pose with a residual.
constexpr int kMinCorners = 4;

// Every chessboard corner next to a detected marker, placed through the homography of each such
// marker (board plane to image, from its four edge-accurate corners) and averaged over them.
// OpenCV's interpolateCornersCharuco does the same and then runs cornerSubPix, which on a
// binarised image lands on a pixel centre (measured: 0.5 px off in x and y on exact renderings).
void locate_chessboard_corners(const cv::aruco::CharucoBoard& board,
                               const std::vector<std::vector<cv::Point2f>>& marker_corners,
                               const std::vector<int>& marker_ids,
                               std::vector<cv::Point2f>& corners, std::vector<int>& corner_ids) {
  std::map<int, cv::Matx33d> homography;  // by index into board.ids
  for (std::size_t i = 0; i < marker_ids.size(); ++i) {
    const auto it = std::find(board.ids.begin(), board.ids.end(), marker_ids[i]);
    if (it == board.ids.end()) continue;
    const auto index = static_cast<std::size_t>(it - board.ids.begin());
    std::vector<cv::Point2f> plane;
    for (const cv::Point3f& p : board.objPoints[index]) plane.emplace_back(p.x, p.y);
    homography[static_cast<int>(index)] = cv::getPerspectiveTransform(plane, marker_corners[i]);
  }
  for (std::size_t c = 0; c < board.chessboardCorners.size(); ++c) {
    const cv::Point3f& b = board.chessboardCorners[c];
    cv::Point2d sum(0, 0);
    int n = 0;
    for (int index : board.nearestMarkerIdx[c]) {
      const auto h = homography.find(index);
      if (h == homography.end()) continue;
      const cv::Vec3d q = h->second * cv::Vec3d(b.x, b.y, 1);
      sum += cv::Point2d(q[0] / q[2], q[1] / q[2]);
      ++n;
    }
    if (n == 0) continue;
    corners.emplace_back(static_cast<float>(sum.x / n), static_cast<float>(sum.y / n));
    corner_ids.push_back(static_cast<int>(c));
  }
}

class CharucoDetector final : public MarkerDetector {
 public:
  CharucoDetector(const std::string& board, const ArucoOptions& options)
      : name_("charuco:" + board),
        spec_(parse_charuco_board(board)),
        dictionary_(cv::aruco::getPredefinedDictionary(spec_.dictionary->id)),
        parameters_(aruco_parameters(options)),
        options_(options) {}

  const std::string& family() const override { return name_; }

  void detect(const cv::Mat& gray, std::vector<Detection>& out) override {
    CV_Assert(gray.type() == CV_8UC1);
    std::vector<std::vector<cv::Point2f>> corners;
    std::vector<int> ids;
    cv::aruco::detectMarkers(gray, dictionary_, corners, ids, parameters_);
    // The board's markers sit in white squares with a one-cell white margin: the ArUco back-end's
    // shape and quiet-zone filter applies as is.
    std::map<int, std::pair<std::vector<std::vector<cv::Point2f>>, std::vector<int>>> by_board;
    const int border = spec_.marker_bits + 2;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      std::vector<Vec2> quad;
      for (const cv::Point2f& c : corners[i]) quad.emplace_back(c.x, c.y);
      to_edge_convention(options_.refine, quad);
      if (!plausible_marker_quad(quad, border, options_) ||
          quiet_zone_fraction(gray, quad, border) < options_.min_quiet_zone)
        continue;
      // The marker corners on the true edges: OpenCV starts each chessboard corner's subpixel
      // search from them, and on a binarised image the search does not move off a start half a
      // pixel inside (measured: every corner 0.5 px off in x and y without this).
      std::vector<cv::Point2f> on_edge;
      for (const Vec2& c : quad)
        on_edge.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
      auto& group = by_board[ids[i] / spec_.markers()];
      group.first.push_back(std::move(on_edge));
      group.second.push_back(ids[i]);
    }
    for (auto& [board_id, markers] : by_board) {
      if (markers.second.size() < 2) continue;  // one marker is an ArUco marker, not a board
      std::vector<cv::Point2f> chessboard;
      std::vector<int> corner_ids;
      locate_chessboard_corners(*board_for(board_id), markers.first, markers.second, chessboard,
                                corner_ids);
      if (static_cast<int>(corner_ids.size()) < kMinCorners) continue;
      Detection det;
      det.family = name_;
      det.id = board_id;
      for (std::size_t k = 0; k < corner_ids.size(); ++k) {
        det.corners_px.emplace_back(chessboard[k].x, chessboard[k].y);
        det.keypoints_marker.push_back(charuco_corner_on_board(spec_, corner_ids[k]));
      }
      out.push_back(std::move(det));
    }
  }

 private:
  const cv::Ptr<cv::aruco::CharucoBoard>& board_for(int board_id) {
    auto it = boards_.find(board_id);
    if (it == boards_.end())
      it = boards_.emplace(board_id, make_charuco_board(spec_, board_id, name_)).first;
    return it->second;
  }

  std::string name_;
  CharucoBoardSpec spec_;
  cv::Ptr<cv::aruco::Dictionary> dictionary_;
  cv::Ptr<cv::aruco::DetectorParameters> parameters_;
  ArucoOptions options_;
  std::map<int, cv::Ptr<cv::aruco::CharucoBoard>> boards_;
};

}  // namespace

Vec2 charuco_corner_on_board(const CharucoBoardSpec& spec, int corner_id) {
  // Corner ids run along the rows from the top-left of the board as OpenCV 4.6 draws it
  // (measured, tests/core/test_charuco_detector.cpp); the marker frame is centred on the board,
  // y up, in square edges.
  const int cols = spec.squares_x - 1;
  const int col = corner_id % cols, row = corner_id / cols;
  return Vec2(col + 1 - 0.5 * spec.squares_x, 0.5 * spec.squares_y - (row + 1));
}

std::unique_ptr<MarkerDetector> make_charuco_detector(const std::string& board,
                                                      const ArucoOptions& options) {
  check_aruco_options(options);
  return std::make_unique<CharucoDetector>(board, options);
}

std::vector<std::string> charuco_example_families() {
  return {"DICT_4X4_50:5x5", "DICT_4X4_50:5x7", "DICT_5X5_100:7x9", "DICT_6X6_250:8x11"};
}

FamilyLayout charuco_layout(const std::string& board) {
  const CharucoBoardSpec spec = parse_charuco_board(board);
  const cv::Ptr<cv::aruco::Dictionary> dictionary =
      cv::aruco::getPredefinedDictionary(spec.dictionary->id);
  // The unit of size is one chessboard square; the print adds one white cell around the board.
  return FamilyLayout{
      spec.square_cells(), std::max(spec.squares_x, spec.squares_y) * spec.square_cells() + 2,
      2 * dictionary->maxCorrectionBits + 1, dictionary->bytesList.rows / spec.markers()};
}

}  // namespace iilfm::detail
