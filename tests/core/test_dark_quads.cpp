// Dark squares for ring-sample decoding: the black square of a marker read from sparse rings, with
// border rows missing and white data cells cutting into it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "../../src/dark_quads.hpp"

namespace iilfm {
namespace {

constexpr int kCells = 8;  // tag36h11's black square, border included
constexpr int kCell = 6;   // pixels a cell

// A white image with an 8 x 8-cell black square whose top-left corner is at (x0, y0), and the
// cells listed (column, row) painted white.
cv::Mat square_with_white_cells(int x0, int y0, const std::vector<cv::Point>& white_cells) {
  cv::Mat image(120, 600, CV_8U, cv::Scalar(255));
  image(cv::Rect(x0, y0, kCells * kCell, kCells * kCell)).setTo(0);
  for (const cv::Point& c : white_cells)
    image(cv::Rect(x0 + c.x * kCell, y0 + c.y * kCell, kCell, kCell)).setTo(255);
  return image;
}

// How far the quad nearest `corners` lies from them: over the corners, the largest distance to
// that quad's nearest corner (1e9 without quads).
double distance_to_nearest_quad(const std::vector<std::array<Vec2, 4>>& quads,
                                const std::array<Vec2, 4>& corners) {
  double best = 1e9;
  for (const std::array<Vec2, 4>& quad : quads) {
    double worst = 0;
    for (const Vec2& corner : corners) {
      double nearest = 1e9;
      for (const Vec2& q : quad) nearest = std::min(nearest, (q - corner).norm());
      worst = std::max(worst, nearest);
    }
    best = std::min(best, worst);
  }
  return best;
}

// The corners of the dark part of the square at (x0, y0) below its first `rows_gone` rows, as
// the outermost pixel centres (what the fitted sides run through).
std::array<Vec2, 4> dark_corners(int x0, int y0, int rows_gone = 0) {
  const double top = y0 + rows_gone * kCell;
  const double x1 = x0 + kCells * kCell - 1, y1 = y0 + kCells * kCell - 1;
  return {Vec2(x0, top), Vec2(x1, top), Vec2(x1, y1), Vec2(x0, y1)};
}

TEST(DarkQuads, ASquareCutInTwoByAWhitePathIsFoundWhole) {
  // The top border row missing (no ring crossed it), and a white path of data cells from there
  // down to a gap in the bottom border, turning on its way (as in a VLP-16 Hi-Res scan of a 40 cm
  // tag36h11 at 2.5 m): two blobs whose boxes touch, neither of them the square.
  std::vector<cv::Point> white;
  for (int col = 0; col < kCells; ++col) white.emplace_back(col, 0);
  for (int row = 1; row <= 3; ++row) white.emplace_back(4, row);
  for (int row = 3; row < kCells; ++row) white.emplace_back(3, row);
  const cv::Mat image = square_with_white_cells(100, 30, white);
  const std::array<Vec2, 4> expected = dark_corners(100, 30, 1);
  const auto without_pairs = detail::dark_quads(image, 2.0 * kCells, 0);
  EXPECT_GT(distance_to_nearest_quad(without_pairs, expected), 10.0);
  const auto quads = detail::dark_quads(image, 2.0 * kCells, kCells);
  EXPECT_LT(distance_to_nearest_quad(quads, expected), 1.0);
}

TEST(DarkQuads, ASquareWithACornerCutOffIsFoundWhole) {
  // The top border row missing and white data cells around a 2 x 2-cell piece in the top-left
  // corner: a small piece beside a large blob, neither box overlapping the other by half, and the
  // large blob's hull alone cuts the corner off (as in ULTRA Puck scans of 40 cm and 1 m tags at
  // 5-14 m).
  std::vector<cv::Point> white;
  for (int col = 0; col < kCells; ++col) white.emplace_back(col, 0);
  for (const cv::Point& cell :
       {cv::Point(2, 1), cv::Point(2, 2), cv::Point(0, 3), cv::Point(1, 3), cv::Point(2, 3)})
    white.push_back(cell);
  const cv::Mat image = square_with_white_cells(100, 30, white);
  const std::array<Vec2, 4> expected = dark_corners(100, 30, 1);
  EXPECT_GT(distance_to_nearest_quad(detail::dark_quads(image, 2.0 * kCells, 0), expected), 1.0);
  EXPECT_LT(distance_to_nearest_quad(detail::dark_quads(image, 2.0 * kCells, kCells), expected),
            1.0);
}

TEST(DarkQuads, ATenPixelSquareWithCornersCutByTwoPixelsIsFound) {
  // An OS1-64's 1 m tag36h11 at 16 m in the square-pixel image: 10 columns by 10 rows (5 rings),
  // cut in two by a column of white data cells, the bottom ring grazing the lower corners, which
  // the binary image cuts by two pixels on the left and one on the right. The pair's hull is a
  // hexagon, off its quadrilateral by 1.4 pixels, more than 4 % of its outline.
  cv::Mat image(60, 200, CV_8U, cv::Scalar(255));
  image(cv::Rect(100, 20, 10, 10)).setTo(0);
  image(cv::Rect(104, 20, 1, 10)).setTo(255);
  for (const cv::Point& p : {cv::Point(100, 28), cv::Point(100, 29), cv::Point(101, 29),
                             cv::Point(101, 28), cv::Point(109, 29)})
    image.at<std::uint8_t>(p) = 255;
  const std::array<Vec2, 4> expected = {Vec2(100, 20), Vec2(109, 20), Vec2(109, 29), Vec2(100, 29)};
  EXPECT_LT(distance_to_nearest_quad(detail::dark_quads(image, 9.5, kCells), expected), 1.0);
  // A square of 40 pixels with the same cut keeps the 4 % tolerance, and is found too.
  cv::Mat large(120, 300, CV_8U, cv::Scalar(255));
  large(cv::Rect(100, 20, 40, 40)).setTo(0);
  large(cv::Rect(100, 58, 2, 2)).setTo(255);
  EXPECT_LT(distance_to_nearest_quad(detail::dark_quads(large, 20, kCells),
                                     {Vec2(100, 20), Vec2(139, 20), Vec2(139, 59), Vec2(100, 59)}),
            1.0);
}

TEST(DarkQuads, ASpeckJoinedToASideIsLeftOut) {
  // An OS1-128's 1 m tag36h11 at 23 m in the square-pixel image (seed 9): a 13 x 12-pixel square
  // with a dark speck of the wall standing four pixels above its top side, joined to it by a ring
  // that grazed the edge, and a bump of the bottom ring's mixed pixels below it. The hull is a
  // hexagon whose spike approxPolyDP keeps; four of its vertices are the square (not found
  // before: a hull had to reduce to four vertices).
  cv::Mat image(60, 200, CV_8U, cv::Scalar(255));
  image(cv::Rect(100, 24, 13, 12)).setTo(0);
  image(cv::Rect(103, 27, 3, 3)).setTo(255);  // white data cells
  image(cv::Rect(107, 30, 3, 3)).setTo(255);
  image(cv::Rect(107, 20, 1, 4)).setTo(0);  // the speck, one pixel wide
  image(cv::Rect(104, 36, 2, 1)).setTo(0);  // the bottom ring's bump
  const std::array<Vec2, 4> expected = {Vec2(100, 24), Vec2(112, 24), Vec2(112, 35), Vec2(100, 35)};
  EXPECT_LT(distance_to_nearest_quad(detail::dark_quads(image, 10, kCells), expected), 1.0);
  // Four vertices that turn too far from a parallelogram are no square: a wedge is not one.
  cv::Mat wedge(60, 200, CV_8U, cv::Scalar(255));
  std::vector<cv::Point> outline = {{100, 40}, {104, 20}, {112, 18}, {130, 30}, {118, 40}};
  cv::fillConvexPoly(wedge, outline, 0);
  EXPECT_TRUE(detail::dark_quads(wedge, 10, kCells).empty());
}

TEST(DarkQuads, ASquareARingShortIsFoundWhenItsHeightMayBe) {
  // An OS1-64's 1 m tag36h11 at 16 m in the square-pixel image (seeds 9 and 10): 10 pixels wide
  // and 8 tall, its bottom border row between two rings of 2 pixels each lost. Ring decoding asks
  // for 10 pixels of width and lets the height fall a ring spacing short.
  cv::Mat image(60, 200, CV_8U, cv::Scalar(255));
  image(cv::Rect(100, 20, 10, 8)).setTo(0);
  image(cv::Rect(102, 22, 2, 2)).setTo(255);  // white data cells
  image(cv::Rect(106, 24, 2, 4)).setTo(255);
  EXPECT_TRUE(detail::dark_quads(image, 10, kCells).empty());
  const std::array<Vec2, 4> expected = {Vec2(100, 20), Vec2(109, 20), Vec2(109, 27), Vec2(100, 27)};
  EXPECT_LT(distance_to_nearest_quad(detail::dark_quads(image, 10, kCells, 8.0), expected), 1.0);
  EXPECT_TRUE(detail::dark_quads(image, 10, kCells, 8.5).empty());
}

TEST(DarkQuads, APairOfOnePixelWidePartsCountsItsPixels) {
  // A square's two halves, each a column with one-pixel rows off it and white rows between (rings
  // one pixel apart): their outlines enclose almost no area, but their pixels cover more than half
  // the square, and the pair is tried.
  cv::Mat image(60, 200, CV_8U, cv::Scalar(255));
  image(cv::Rect(100, 20, 1, 13)).setTo(0);
  image(cv::Rect(111, 20, 1, 13)).setTo(0);
  for (int y = 20; y <= 32; y += 2) {
    image(cv::Rect(100, y, 5, 1)).setTo(0);
    image(cv::Rect(106, y, 6, 1)).setTo(0);
  }
  const std::array<Vec2, 4> expected = {Vec2(100, 20), Vec2(111, 20), Vec2(111, 32), Vec2(100, 32)};
  EXPECT_LT(distance_to_nearest_quad(detail::dark_quads(image, 10, kCells), expected), 1.0);
}

TEST(DarkQuads, ASideFittedAcrossAGrazedRowIsAlsoLaidParallelToItsOpposite) {
  // A 16-pixel square whose bottom border row a ring grazed: its left part reads white, so the
  // hull's bottom edge slopes and the side fitted along it turns 13 degrees from the top one (an
  // OS1-128's 1 m tag at 20 m, seed 1). The square is also given with that side laid parallel to
  // the top through its points' median.
  cv::Mat image(60, 200, CV_8U, cv::Scalar(255));
  image(cv::Rect(100, 20, 16, 16)).setTo(0);
  image(cv::Rect(104, 24, 4, 4)).setTo(255);  // white data cells
  image(cv::Rect(108, 28, 4, 4)).setTo(255);
  image(cv::Rect(100, 34, 6, 2)).setTo(255);  // the grazed part of the bottom row
  const auto quads = detail::dark_quads(image, 10, kCells);
  ASSERT_EQ(quads.size(), 2u);
  const std::array<Vec2, 4> expected = {Vec2(100, 20), Vec2(115, 20), Vec2(115, 35), Vec2(100, 35)};
  EXPECT_GT(distance_to_nearest_quad({quads[0]}, expected), 2.0);  // as fitted
  EXPECT_LT(distance_to_nearest_quad({quads[1]}, expected), 0.5);
}

TEST(DarkQuads, NotchesOfWhiteCellsDoNotPullASideIn) {
  // White data cells along the inside of the top border row that no ring crossed: the top side is
  // a castle wall, whose tops are the side.
  std::vector<cv::Point> white;
  for (int col = 0; col < kCells; ++col) white.emplace_back(col, 0);
  for (int col : {1, 3, 4, 6}) white.emplace_back(col, 1);
  const cv::Mat image = square_with_white_cells(100, 30, white);
  const auto quads = detail::dark_quads(image, 2.0 * kCells, kCells);
  EXPECT_LT(distance_to_nearest_quad(quads, dark_corners(100, 30, 1)), 1.0);
}

TEST(DarkQuads, ASquareOpenAtAMissingBorderRowIsFound) {
  // The top border row missing and the data cells under it white, down into a white middle: the
  // blob is a cup, whose outline encloses little more than its own pixels, though more than half
  // the square is dark (an OS1-64's 40 cm tag at 5-6 m).
  std::vector<cv::Point> white;
  for (int col = 0; col < kCells; ++col) white.emplace_back(col, 0);
  for (int row = 1; row <= 3; ++row)
    for (int col = 1; col <= 6; ++col) white.emplace_back(col, row);
  for (int row = 4; row <= 5; ++row)
    for (int col = 3; col <= 4; ++col) white.emplace_back(col, row);
  const cv::Mat image = square_with_white_cells(100, 30, white);
  const auto quads = detail::dark_quads(image, 2.0 * kCells, kCells);
  EXPECT_LT(distance_to_nearest_quad(quads, dark_corners(100, 30, 1)), 1.0);
}

TEST(DarkQuads, ASideWithTooFewOutlinePointsIsTheHullsEdge) {
  // The top border row missing and the two data rows under it white: along the top, between the
  // side columns, the outline lies two cell rows down, too deep to fit a side to. The hull's edge
  // is the side (ring decoding then searches where it lies).
  std::vector<cv::Point> white;
  for (int col = 0; col < kCells; ++col) white.emplace_back(col, 0);
  for (int row = 1; row <= 2; ++row)
    for (int col = 1; col <= 6; ++col) white.emplace_back(col, row);
  const cv::Mat image = square_with_white_cells(100, 30, white);
  const auto quads = detail::dark_quads(image, 2.0 * kCells, kCells);
  EXPECT_LT(distance_to_nearest_quad(quads, dark_corners(100, 30, 1)), 1.0);
}

TEST(DarkQuads, NeighbouringSquaresAreNotJoined) {
  // Squares side by side with the white margins of two markers between them (two cells), and
  // with one marker's margin alone (one cell).
  const int side = kCells * kCell;
  const int x1 = 100, x2 = x1 + side + 2 * kCell, x3 = x2 + side + kCell;
  cv::Mat image = square_with_white_cells(x1, 30, {});
  image(cv::Rect(x2, 30, side, side)).setTo(0);
  image(cv::Rect(x3, 30, side, side)).setTo(0);
  const auto quads = detail::dark_quads(image, 2.0 * kCells, kCells);
  ASSERT_EQ(quads.size(), 3u);
  for (int x : {x1, x2, x3}) EXPECT_LT(distance_to_nearest_quad(quads, dark_corners(x, 30)), 1.0);
}

}  // namespace
}  // namespace iilfm
