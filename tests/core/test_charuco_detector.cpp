// ChArUco boards: one detection per board, every chessboard corner a keypoint at its place on the
// board, checked against OpenCV's own drawing.
#include <gtest/gtest.h>

#include <cstdio>
#include <opencv2/aruco.hpp>
#include <opencv2/imgproc.hpp>

#include "iilfm/charuco_boards.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"

namespace iilfm {
namespace {

constexpr int kPxPerCell = 6;
constexpr int kMargin = 3;  // white cells around the board

std::vector<Detection> detect(const std::string& family, const cv::Mat& image) {
  std::vector<Detection> found;
  make_detector(family)->detect(image, found);
  return found;
}

// Each keypoint lies where its marker-frame coordinates put it on the drawn board: the board's
// centre at the image centre, one square = square_cells() * kPxPerCell pixels, y up.
TEST(Charuco, EveryCornerIsFoundWhereItsMarkerFrameCoordinatesSay) {
  for (const std::string board : {"DICT_4X4_50:5x7", "DICT_5X5_100:6x4"}) {
    const std::string family = "charuco:" + board;
    const CharucoBoardSpec spec = parse_charuco_board(board);
    const cv::Mat image = draw_charuco_cells(spec, 0, family, kMargin, kPxPerCell);
    const std::vector<Detection> found = detect(family, image);
    ASSERT_EQ(found.size(), 1u) << family;
    const Detection& d = found[0];
    EXPECT_EQ(d.family, family);
    EXPECT_EQ(d.id, 0);
    ASSERT_EQ(d.corners_px.size(), static_cast<std::size_t>(spec.corners())) << family;
    ASSERT_EQ(d.keypoints_marker.size(), d.corners_px.size());
    const double square_px = spec.square_cells() * kPxPerCell;
    // Pixel centres at integers: the image's centre line is at (cols - 1) / 2.
    const Vec2 centre((image.cols - 1) / 2.0, (image.rows - 1) / 2.0);
    double worst = 0;
    for (std::size_t k = 0; k < d.corners_px.size(); ++k) {
      const Vec2& m = d.keypoints_marker[k];
      const Vec2 expected = centre + square_px * Vec2(m.x(), -m.y());
      worst = std::max(worst, (d.corners_px[k] - expected).norm());
    }
    std::printf("[ measured ] %s on OpenCV's drawing: worst corner %.3f px\n", family.c_str(),
                worst);
    EXPECT_LT(worst, 0.3) << family;
    // The outline is the hull of the corners: (cols - 2) x (rows - 2) squares.
    std::vector<cv::Point2f> hull;
    for (const Vec2& p : keypoint_outline(d)) hull.emplace_back(p.x(), p.y());
    EXPECT_NEAR(cv::contourArea(hull) / (square_px * square_px),
                (spec.squares_x - 2) * (spec.squares_y - 2), 0.05);
  }
}

TEST(Charuco, BoardIdsUseTheirOwnMarkerIdsAndLoneMarkersAreNoBoard) {
  const std::string family = "charuco:DICT_4X4_50:3x3";  // 4 markers, 4 corners per board
  const CharucoBoardSpec spec = parse_charuco_board("DICT_4X4_50:3x3");
  const cv::Mat board2 = draw_charuco_cells(spec, 2, family, kMargin, kPxPerCell);
  const std::vector<Detection> found = detect(family, board2);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 2);
  EXPECT_EQ(found[0].corners_px.size(), 4u);

  // One marker of the dictionary on white paper is an ArUco marker, not a board.
  cv::Mat marker;
  cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50)->drawMarker(1, 60, marker, 1);
  cv::Mat sheet;
  cv::copyMakeBorder(marker, sheet, 30, 30, 30, 30, cv::BORDER_CONSTANT, cv::Scalar(255));
  EXPECT_TRUE(detect(family, sheet).empty());
  EXPECT_EQ(detect("aruco:DICT_4X4_50", sheet).size(), 1u);
}

TEST(Charuco, MalformedBoardNamesAreInputErrors) {
  for (const std::string bad :
       {"charuco:DICT_4X4_50", "charuco:DICT_4X4_50:2x5", "charuco:DICT_FOO:5x5",
        "charuco:DICT_4X4_50:5x5x", "charuco:DICT_4X4_50:20x20"}) {
    EXPECT_THROW(make_detector(bad), InputError) << bad;
    EXPECT_THROW(family_layout(bad), InputError) << bad;
  }
  EXPECT_THROW(make_charuco_board(parse_charuco_board("DICT_4X4_50:5x5"), 4, "x"), InputError);
  EXPECT_EQ(family_layout("charuco:DICT_4X4_50:5x7").border_width, 8);
}

}  // namespace
}  // namespace iilfm
