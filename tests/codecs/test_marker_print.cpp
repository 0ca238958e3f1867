// `iilfm marker print`: every family (and example ChArUco board) prints at the asked size (black
// square within a pixel of size * dpi / 0.0254), carries its resolution, and decodes with iilfm's
// own detectors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <regex>

#include "cli_run.hpp"
#include "iilfm/charuco_boards.hpp"
#include "iilfm/detector.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm {
namespace {

namespace fs = std::filesystem;

using testing::CliRun;
using testing::run_cli;
using testing::slurp;

constexpr double kInch = 0.0254;

fs::path temp(const std::string& name) { return iilfm::testing::process_scratch_dir() / name; }

double mean_edge(const std::vector<Vec2>& c) {
  double sum = 0;
  for (std::size_t k = 0; k < 4; ++k) sum += (c[(k + 1) % 4] - c[k]).norm();
  return sum / 4;
}

// The outer black square measured on the pixels: its top border's first row, then the black run
// two rows below it (left to right) and the black run down the column two pixels inside it.
cv::Size measured_black_square(const cv::Mat& image) {
  int top = 0;
  while (top < image.rows && cv::countNonZero(image.row(top) < 128) == 0) ++top;
  const int row = top + 2;
  int left = 0;
  while (left < image.cols && image.at<std::uint8_t>(row, left) >= 128) ++left;
  int right = left;
  while (right < image.cols && image.at<std::uint8_t>(row, right) < 128) ++right;
  const int col = left + 2;
  int bottom = top;
  while (bottom < image.rows && image.at<std::uint8_t>(bottom, col) < 128) ++bottom;
  return {right - left, bottom - top};
}

std::uint32_t big_endian(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<std::uint8_t>(bytes[at + i]);
  return v;
}

TEST(MarkerPrint, EveryFamilyPrintsAtSizeAndDecodesWithItsId) {
  const double dpi = 150;
  const std::vector<std::string> families = known_families();
  ASSERT_EQ(families.size(), 36u);  // 9 AprilTag, 21 ArUco, 4 example ChArUco boards, 2 rings
  for (const std::string& family : families) {
    const bool board = family.rfind("charuco:", 0) == 0;
    const int id = board ? 1 : 5;  // board 1 of DICT_4X4_50:5x7 uses marker ids 17..33
    const FamilyLayout layout = family_layout(family);
    // About 7.3 px per cell (boards 5.3, LiDAR-like: the ArUco back-end's threshold windows of
    // 3-23 px lose DICT_6X6 board markers above about 10 px per cell): a size that is no whole
    // number of pixels.
    const double size = (board ? 5.3 : 7.3) * layout.border_width * kInch / dpi;
    const double expected_px = size * dpi / kInch;
    const fs::path png = temp("print.png");
    char size_text[32];
    std::snprintf(size_text, sizeof size_text, "%.9f", size);
    const CliRun r = run_cli("marker print " + family + " " + std::to_string(id) + " --size " +
                             size_text + " --dpi 150 --out " + png.string());
    ASSERT_EQ(r.status, 0) << family << ": " << r.err;

    const cv::Mat image = cv::imread(png.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << family;
    std::vector<Detection> found;
    make_detector(family)->detect(image, found);
    ASSERT_EQ(found.size(), 1u) << family;
    EXPECT_EQ(found[0].id, id) << family;
    if (board) {
      // Most chessboard corners (markers with a bit at the threshold windows' limit may be
      // lost), neighbours one square (the size) apart.
      const CharucoBoardSpec spec = parse_charuco_board(family.substr(8));
      const Detection& d = found[0];
      EXPECT_GE(2 * d.corners_px.size(), static_cast<std::size_t>(spec.corners())) << family;
      int pairs = 0;
      for (std::size_t a = 0; a < d.corners_px.size(); ++a)
        for (std::size_t b = 0; b < d.corners_px.size(); ++b)
          if ((d.keypoints_marker[b] - d.keypoints_marker[a] - Vec2(1, 0)).norm() < 1e-9) {
            EXPECT_NEAR((d.corners_px[b] - d.corners_px[a]).norm(), expected_px, 1.0) << family;
            ++pairs;
          }
      EXPECT_GT(pairs, 0) << family;
    } else if (family.rfind("rings:", 0) == 0) {
      // One keypoint, the centre: the row through it crosses the outer diameter of ink, and the
      // fitted outline is that diameter wide.
      const Detection& d = found[0];
      ASSERT_EQ(d.corners_px.size(), 1u);
      const int row = static_cast<int>(std::lround(d.corners_px[0].y()));
      int left = 0, right = image.cols - 1;
      while (left < image.cols && image.at<std::uint8_t>(row, left) >= 128) ++left;
      while (right > left && image.at<std::uint8_t>(row, right) >= 128) --right;
      EXPECT_NEAR(right - left + 1, expected_px, 1.0) << family;
      EXPECT_NEAR(d.corners_px[0].x(), 0.5 * (left + right), 0.5) << family;
      double radius = 0;
      for (const Vec2& p : d.outline_px)
        radius += (p - d.corners_px[0]).norm() / d.outline_px.size();
      EXPECT_NEAR(2 * radius, expected_px, 1.5) << family;
    } else {
      // The detector's corners span the reported square (all families, circle ones included).
      EXPECT_NEAR(mean_edge(found[0].corners_px), expected_px, 1.0) << family;
    }
    // Where the reported square is the outermost ink (one white cell around it in the family's
    // own image), the pixels show it directly.
    if (layout.total_width - layout.border_width == 2) {
      const cv::Size black = measured_black_square(image);
      EXPECT_NEAR(black.width, expected_px, 1.0) << family;
      EXPECT_NEAR(black.height, expected_px, 1.0) << family;
    }
    // The PNG says its resolution: a pHYs chunk in pixels per metre.
    const std::string bytes = slurp(png);
    const std::size_t phys = bytes.find("pHYs");
    ASSERT_NE(phys, std::string::npos) << family;
    EXPECT_EQ(big_endian(bytes, phys + 4), static_cast<std::uint32_t>(std::lround(dpi / kInch)));
    EXPECT_EQ(bytes[phys + 12], 1) << "unit: metre";
  }
}

TEST(MarkerPrint, A300DpiTagDecodesThroughTheImageInputPath) {
  const fs::path png = temp("tag300.png"), json = temp("tag300.json");
  const CliRun r = run_cli("marker print apriltag:tag36h11 17 --size 0.05 --out " + png.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("square 591 px"), std::string::npos) << r.out;  // 0.05 m * 300 / 0.0254
  const CliRun d =
      run_cli("detect " + png.string() +
              " --res-h 0.1 --res-v 0.1 --marker apriltag:tag36h11 -q --json " + json.string());
  ASSERT_EQ(d.status, 0) << d.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j["markers"].size(), 1u);
  EXPECT_EQ(j["markers"][0]["id"], 17);
}

TEST(MarkerPrint, SvgBlackCellsSpanTheSquareInMillimetres) {
  const fs::path png = temp("svg.png"), svg = temp("svg.svg");
  const CliRun r = run_cli("marker print aruco:DICT_5X5_100 42 --size 0.123 --out " + png.string() +
                           " --svg " + svg.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string text = slurp(svg);
  const std::regex rect(
      "<rect x=\"([0-9.e+-]+)\" y=\"([0-9.e+-]+)\" width=\"([0-9.e+-]+)\" "
      "height=\"([0-9.e+-]+)\" fill=\"#000\"");
  double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
  int rects = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), rect); it != std::sregex_iterator();
       ++it, ++rects) {
    const double x = std::stod((*it)[1]), y = std::stod((*it)[2]);
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x + std::stod((*it)[3]));
    y1 = std::max(y1, y + std::stod((*it)[4]));
  }
  EXPECT_GT(rects, 7);  // at least the border's rows
  EXPECT_NEAR(x1 - x0, 123.0, 1e-6);
  EXPECT_NEAR(y1 - y0, 123.0, 1e-6);
  EXPECT_NE(text.find("mm\" height=\""), std::string::npos);
  EXPECT_NE(text.find("aruco:DICT_5X5_100  id 42"), std::string::npos);
}

TEST(MarkerPrint, BadRequestsAreOneLineErrors) {
  const fs::path png = temp("bad.png");
  const std::pair<std::string, std::string> cases[] = {
      {"marker print apriltag:tag99h1 0 --size 0.1", "unknown AprilTag family"},
      {"marker print aruco:DICT_4X4_50 50 --size 0.1", "outside aruco:DICT_4X4_50"},
      {"marker print apriltag:tag36h11 0 --size 0.002 --dpi 72", "fewer than 2 px per cell"},
      {"marker print apriltag:tag36h11 0 --size -1", "--size must be a positive"},
  };
  for (const auto& [args, message] : cases) {
    fs::remove(png);
    const CliRun r = run_cli(args + " --out " + png.string());
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_FALSE(fs::exists(png)) << args;
  }
}

}  // namespace
}  // namespace iilfm
