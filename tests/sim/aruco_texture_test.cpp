// ArUco textures come from OpenCV's drawMarker with the geometry the simulator relies on: the
// black square spans width_at_border cells inside a one-cell white margin, and the print decodes
// with OpenCV's detector to its id with the corners in the canonical order (top-left, top-right,
// bottom-right, bottom-left of the outer black square as the upright print is seen).
#include <gtest/gtest.h>

#include <opencv2/aruco.hpp>

#include "iilfm/aruco_dictionaries.hpp"
#include "iilfm/error.hpp"
#include "iilfm/sim/marker_texture.hpp"

namespace iilfm::sim {
namespace {

constexpr int kCellPx = 12;  // upscaled print: pixels per cell
constexpr int kPadPx = 40;   // extra white around the sheet

// The texture at kCellPx pixels per cell on a white page, turned by quarter_turns x 90 deg
// counter-clockwise.
cv::Mat page_of(const MarkerTexture& t, int quarter_turns) {
  const int side = t.total_width * kCellPx + 2 * kPadPx;
  cv::Mat page(side, side, CV_8UC1, cv::Scalar(255));
  for (int r = 0; r < t.total_width * kCellPx; ++r)
    for (int c = 0; c < t.total_width * kCellPx; ++c)
      page.at<std::uint8_t>(kPadPx + r, kPadPx + c) =
          t.pixels[(r / kCellPx) * t.total_width + c / kCellPx];
  for (int k = 0; k < quarter_turns; ++k) cv::rotate(page, page, cv::ROTATE_90_COUNTERCLOCKWISE);
  return page;
}

// Canonical corners of the black square on the upright page (pixel centres at integers, so an
// edge between pixels lies at .5), turned like page_of.
std::array<cv::Point2f, 4> expected_corners(const MarkerTexture& t, int quarter_turns) {
  const float side = t.total_width * kCellPx + 2 * kPadPx;
  const float lo = kPadPx + kCellPx - 0.5f;
  const float hi = kPadPx + (t.total_width - 1) * kCellPx - 0.5f;
  std::array<cv::Point2f, 4> c = {cv::Point2f(lo, lo), cv::Point2f(hi, lo), cv::Point2f(hi, hi),
                                  cv::Point2f(lo, hi)};
  for (int k = 0; k < quarter_turns; ++k)
    for (cv::Point2f& p : c) p = cv::Point2f(p.y, side - 1 - p.x);  // 90 deg counter-clockwise
  return c;
}

struct Decoded {
  int id = -1;
  std::vector<cv::Point2f> corners;
};

std::vector<Decoded> decode(const cv::Mat& page, const std::string& family) {
  const ArucoDictionaryEntry* entry =
      find_aruco_dictionary(family.substr(std::string("aruco:").size()));
  if (!entry) {
    ADD_FAILURE() << "no dictionary " << family;
    return {};
  }
  const auto dict = cv::aruco::getPredefinedDictionary(entry->id);
  auto params = cv::aruco::DetectorParameters::create();
  params->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids;
  cv::aruco::detectMarkers(page, dict, corners, ids, params);
  std::vector<Decoded> out;
  for (std::size_t i = 0; i < ids.size(); ++i) out.push_back({ids[i], corners[i]});
  return out;
}

TEST(ArucoTexture, Dict4x4HasAWhiteMarginAroundTheBlackBorderAndDrawMarkersBits) {
  const MarkerTexture t = render_marker_texture("aruco:DICT_4X4_50", 7);
  ASSERT_EQ(t.total_width, 8);
  ASSERT_EQ(t.width_at_border, 6);
  ASSERT_EQ(t.pixels.size(), 64u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_FALSE(t.is_black(0, i));
    EXPECT_FALSE(t.is_black(7, i));
    EXPECT_FALSE(t.is_black(i, 0));
    EXPECT_FALSE(t.is_black(i, 7));
  }
  for (int i = 1; i < 7; ++i) {
    EXPECT_TRUE(t.is_black(1, i));
    EXPECT_TRUE(t.is_black(6, i));
    EXPECT_TRUE(t.is_black(i, 1));
    EXPECT_TRUE(t.is_black(i, 6));
  }
  // The data cells are drawMarker's, bit for bit, not turned or mirrored.
  cv::Mat drawn;
  cv::aruco::getPredefinedDictionary(cv::aruco::DICT_4X4_50)->drawMarker(7, 6, drawn, 1);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c)
      EXPECT_EQ(t.is_black(r + 1, c + 1), drawn.at<std::uint8_t>(r, c) < 128) << r << "," << c;
}

TEST(ArucoTexture, EveryDictionaryHasItsOwnSizeAndRendersItsLastId) {
  const std::vector<std::string> families = aruco_family_names();
  ASSERT_EQ(families.size(), 21u);
  EXPECT_EQ(marker_family_names().size(), 32u);  // + rings:ring7h3, rings:ring9h3
  EXPECT_EQ(render_marker_texture("aruco:DICT_ARUCO_ORIGINAL", 1023).width_at_border, 7);
  EXPECT_EQ(render_marker_texture("aruco:DICT_7X7_1000", 999).total_width, 11);
  EXPECT_EQ(render_marker_texture("aruco:DICT_APRILTAG_36h11", 586).width_at_border, 8);
  EXPECT_EQ(render_marker_texture("aruco:DICT_APRILTAG_16h5", 29).width_at_border, 6);
}

TEST(ArucoTexture, EveryDictionaryDecodesToItsIdWithCanonicalCornersInEveryTurn) {
  for (const std::string& family : aruco_family_names()) {
    const int id = family.find("_50") != std::string::npos ? 37 : 29;  // inside every dictionary
    const MarkerTexture t = render_marker_texture(family, id);
    for (int turns = 0; turns < 4; ++turns) {
      SCOPED_TRACE(family + ", turned " + std::to_string(90 * turns) + " deg");
      const std::vector<Decoded> found = decode(page_of(t, turns), family);
      ASSERT_EQ(found.size(), 1u);
      EXPECT_EQ(found[0].id, id);
      const std::array<cv::Point2f, 4> expected = expected_corners(t, turns);
      for (int k = 0; k < 4; ++k) {
        EXPECT_LT(cv::norm(found[0].corners[k] - expected[k]), 1.0)
            << "corner " << k << " at " << found[0].corners[k] << ", expected " << expected[k];
      }
    }
  }
}

TEST(ArucoTexture, DistinctIdsPrintDistinctPatterns) {
  EXPECT_NE(render_marker_texture("aruco:DICT_ARUCO_ORIGINAL", 0).pixels,
            render_marker_texture("aruco:DICT_ARUCO_ORIGINAL", 1).pixels);
}

TEST(ArucoTexture, UnknownDictionariesAndIdsAreInputErrors) {
  EXPECT_THROW(render_marker_texture("aruco:DICT_9X9_50", 0), InputError);
  EXPECT_THROW(render_marker_texture("aruco:", 0), InputError);
  EXPECT_THROW(render_marker_texture("DICT_4X4_50", 0), InputError);
  EXPECT_THROW(render_marker_texture("aruco:DICT_4X4_50", 50), InputError);
  EXPECT_THROW(render_marker_texture("aruco:DICT_4X4_50", -1), InputError);
  try {
    render_marker_texture("aruco:DICT_4X4_50", 50);
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "marker id 50 is outside aruco:DICT_4X4_50 (0..49)");
  }
}

}  // namespace
}  // namespace iilfm::sim
