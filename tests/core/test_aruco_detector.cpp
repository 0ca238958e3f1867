#include <gtest/gtest.h>

#include <opencv2/aruco.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "../../src/detectors/aruco_detector.hpp"
#include "apriltag_render.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"

namespace iilfm {
namespace {

constexpr int kMargin = 24;  // white pixels around the rendered marker

// A marker as cv::aruco::drawMarker draws it upright, `cell` pixels per cell, on white.
struct Rendered {
  cv::Mat image;
  std::vector<Vec2> corners;  // TL, TR, BR, BL of the black square, pixel centres at integers
};

// OpenCV's dictionary of a name; the list follows PREDEFINED_DICTIONARY_NAME's order.
cv::Ptr<cv::aruco::Dictionary> dictionary(const std::string& name) {
  static const std::vector<std::string> names = {
      "DICT_4X4_50",         "DICT_4X4_100",       "DICT_4X4_250",       "DICT_4X4_1000",
      "DICT_5X5_50",         "DICT_5X5_100",       "DICT_5X5_250",       "DICT_5X5_1000",
      "DICT_6X6_50",         "DICT_6X6_100",       "DICT_6X6_250",       "DICT_6X6_1000",
      "DICT_7X7_50",         "DICT_7X7_100",       "DICT_7X7_250",       "DICT_7X7_1000",
      "DICT_ARUCO_ORIGINAL", "DICT_APRILTAG_16h5", "DICT_APRILTAG_25h9", "DICT_APRILTAG_36h10",
      "DICT_APRILTAG_36h11"};
  const auto it = std::find(names.begin(), names.end(), name);
  return cv::aruco::getPredefinedDictionary(static_cast<int>(it - names.begin()));
}

Rendered render(const std::string& dict, int id, int cell) {
  const auto d = dictionary(dict);
  const int side = (d->markerSize + 2) * cell;
  cv::Mat marker;
  d->drawMarker(id, side, marker, 1);
  Rendered out;
  cv::copyMakeBorder(marker, out.image, kMargin, kMargin, kMargin, kMargin, cv::BORDER_CONSTANT,
                     255);
  // Edges lie between pixels: at (edge index - 0.5) with centres at integers.
  const double lo = kMargin - 0.5, hi = kMargin + side - 0.5;
  out.corners = {Vec2(lo, lo), Vec2(hi, lo), Vec2(hi, hi), Vec2(lo, hi)};
  return out;
}

std::vector<Detection> detect(const std::string& family, const cv::Mat& image,
                              const ArucoOptions& aruco = {}) {
  DetectorOptions options;
  options.aruco = aruco;
  std::vector<Detection> found;
  make_detector(family, options)->detect(image, found);
  return found;
}

void expect_corners(const Detection& d, const std::vector<Vec2>& expected, double tol,
                    const std::string& what) {
  ASSERT_EQ(d.corners_px.size(), 4u) << what;
  for (int k = 0; k < 4; ++k)
    EXPECT_LT((d.corners_px[k] - expected[k]).norm(), tol)
        << what << " corner " << k << ": got " << d.corners_px[k].transpose() << " expected "
        << expected[k].transpose();
}

class ArucoDictionaries : public ::testing::TestWithParam<std::string> {};

TEST_P(ArucoDictionaries, DrawMarkerRenderingComesOutTopLeftFirstAtPixelCentres) {
  const std::string dict = GetParam();
  const Rendered r = render(dict, 3, 6);
  const auto found = detect("aruco:" + dict, r.image);
  ASSERT_EQ(found.size(), 1u) << dict;
  EXPECT_EQ(found[0].id, 3);
  EXPECT_EQ(found[0].family, "aruco:" + dict);
  // Axis-aligned hard edges: contour refinement plus the half-pixel push lands on the edge
  // exactly; a convention slip would be 0.5 px per axis, a wrong order a whole side.
  expect_corners(found[0], r.corners, 0.01, dict);
}

TEST_P(ArucoDictionaries, OrderFollowsThePrintedMarkerWhenTheImageIsRotated) {
  const std::string dict = GetParam();
  const Rendered r = render(dict, 5, 6);
  cv::Mat rotated;
  cv::rotate(r.image, rotated, cv::ROTATE_90_CLOCKWISE);
  // Clockwise: (x, y) -> (H - 1 - y, x); the printed top-left goes to the image's top-right.
  const double n = r.image.rows - 1;
  std::vector<Vec2> expected;
  for (const Vec2& c : r.corners) expected.emplace_back(n - c.y(), c.x());
  const auto found = detect("aruco:" + dict, rotated);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 5);
  expect_corners(found[0], expected, 0.01, dict + " rotated");
}

INSTANTIATE_TEST_SUITE_P(AllDictionaries, ArucoDictionaries,
                         ::testing::Values("DICT_4X4_50", "DICT_4X4_100", "DICT_4X4_250",
                                           "DICT_4X4_1000", "DICT_5X5_50", "DICT_5X5_100",
                                           "DICT_5X5_250", "DICT_5X5_1000", "DICT_6X6_50",
                                           "DICT_6X6_100", "DICT_6X6_250", "DICT_6X6_1000",
                                           "DICT_7X7_50", "DICT_7X7_100", "DICT_7X7_250",
                                           "DICT_7X7_1000", "DICT_ARUCO_ORIGINAL",
                                           "DICT_APRILTAG_16h5", "DICT_APRILTAG_25h9",
                                           "DICT_APRILTAG_36h10", "DICT_APRILTAG_36h11"));

// A LiDAR-like view: the rendering (8 px cells) scaled to `cell` px per cell, rotated by `angle`
// degrees with area averaging, optional noise, binarised at mid-grey. Returns the true corners.
struct Warped {
  cv::Mat image;
  std::vector<Vec2> corners;
};

Warped lidar_like(const Rendered& r, double cell, double angle, double noise_sigma, int seed) {
  const double scale = cell / 8.0;
  const int out = static_cast<int>(r.image.cols * scale * 1.5) + 10;
  cv::Mat M = cv::getRotationMatrix2D(
      cv::Point2f((r.image.cols - 1) / 2.0f, (r.image.rows - 1) / 2.0f), angle, scale);
  M.at<double>(0, 2) += (out - r.image.cols) / 2.0;
  M.at<double>(1, 2) += (out - r.image.rows) / 2.0;
  Warped w;
  cv::warpAffine(r.image, w.image, M, cv::Size(out, out), cv::INTER_AREA, cv::BORDER_CONSTANT, 255);
  if (noise_sigma > 0) {
    cv::Mat noise(w.image.size(), CV_16S);
    cv::theRNG().state = seed;
    cv::randn(noise, 0, noise_sigma);
    cv::Mat sum;
    w.image.convertTo(sum, CV_16S);
    sum += noise;
    sum.convertTo(w.image, CV_8U);
  }
  cv::threshold(w.image, w.image, 127, 255, cv::THRESH_BINARY);
  for (const Vec2& c : r.corners)
    w.corners.emplace_back(
        M.at<double>(0, 0) * c.x() + M.at<double>(0, 1) * c.y() + M.at<double>(0, 2),
        M.at<double>(1, 0) * c.x() + M.at<double>(1, 1) * c.y() + M.at<double>(1, 2));
  return w;
}

struct RefineCase {
  ArucoRefine refine;
  const char* name;
  double max_rms_px, max_mean_radial_px;  // bounds over all cell sizes and angles
  int min_found;                          // of 4 cell sizes x 48 angles
};

class ArucoRefinement : public ::testing::TestWithParam<RefineCase> {};

// Binarised views at 2.5-6 px per cell, every 7.5 degrees. Measured per cell size
// (docs/detectors.md): contour rms 0.06-0.21 px, mean radial offset -0.05..-0.01 px; AprilTag rms
// 0.12-0.22 px, 12 of 48 missed at 2.5 px cells; subpixel rms 0.36-0.62 px, 0.17-0.45 px inward;
// none rms 0.40-0.66 px.
TEST_P(ArucoRefinement, CornersOnRotatedBinarisedViewsStayOnTheEdge) {
  const RefineCase c = GetParam();
  ArucoOptions options;
  options.refine = c.refine;
  options.min_cell_px = 0;
  const Rendered r = render("DICT_4X4_50", 7, 8);
  double sq = 0, radial = 0;
  int found = 0, corners = 0;
  for (double cell : {2.5, 3.0, 4.0, 6.0}) {
    for (double angle = 0; angle < 360; angle += 7.5) {
      const Warped w = lidar_like(r, cell, angle, 0, 0);
      const auto d = detect("aruco:DICT_4X4_50", w.image, options);
      if (d.size() != 1 || d[0].id != 7) continue;
      ++found;
      Vec2 centre = Vec2::Zero();
      for (const Vec2& p : w.corners) centre += p / 4;
      for (int k = 0; k < 4; ++k) {
        const Vec2 err = d[0].corners_px[k] - w.corners[k];
        sq += err.squaredNorm();
        radial += err.dot((w.corners[k] - centre).normalized());
        ++corners;
      }
    }
  }
  EXPECT_GE(found, c.min_found) << c.name;
  ASSERT_GT(corners, 0);
  const double rms = std::sqrt(sq / corners);
  EXPECT_LT(rms, c.max_rms_px) << c.name;
  EXPECT_LT(std::abs(radial / corners), c.max_mean_radial_px) << c.name << " " << radial / corners;
}

INSTANTIATE_TEST_SUITE_P(
    Methods, ArucoRefinement,
    ::testing::Values(RefineCase{ArucoRefine::kContour, "contour", 0.2, 0.05, 192},
                      RefineCase{ArucoRefine::kAprilTag, "apriltag", 0.3, 0.1, 170},
                      RefineCase{ArucoRefine::kSubpixel, "subpixel", 0.7, 0.4, 192},
                      RefineCase{ArucoRefine::kNone, "none", 0.6, 0.2, 192}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(ArucoDetector, FindsNoisyRotatedSmallMarkers) {
  const Rendered r = render("DICT_5X5_100", 42, 8);
  int found = 0;
  double worst = 0;
  for (int seed = 0; seed < 10; ++seed) {
    const Warped w = lidar_like(r, 3.0, 17 + 31 * seed, 25, seed);
    const auto d = detect("aruco:DICT_5X5_100", w.image);
    if (d.size() != 1 || d[0].id != 42) continue;
    ++found;
    for (int k = 0; k < 4; ++k) worst = std::max(worst, (d[0].corners_px[k] - w.corners[k]).norm());
  }
  EXPECT_GE(found, 9);
  EXPECT_LT(worst, 0.8);
}

// The trap: OpenCV's DICT_APRILTAG_* markers are the official AprilTag images turned by 180
// degrees. iilfm's canonical orientation of aruco:DICT_APRILTAG_* is drawMarker's.
TEST(ArucoAprilTagDictionaries, DrawMarkerIsTheOfficialTagTurnedHalfway) {
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"DICT_APRILTAG_16h5", "tag16h5"},
      {"DICT_APRILTAG_25h9", "tag25h9"},
      {"DICT_APRILTAG_36h10", "tag36h10"},
      {"DICT_APRILTAG_36h11", "tag36h11"}};
  for (const auto& [dict, family] : pairs) {
    for (int id : {0, 1, 7, 13}) {
      const cv::Mat tag = testing::render_apriltag(family, id);  // one pixel per cell, margin 1
      cv::Mat drawn;
      dictionary(dict)->drawMarker(id, tag.cols - 2, drawn, 1);
      cv::Mat turned;
      cv::rotate(tag(cv::Rect(1, 1, tag.cols - 2, tag.rows - 2)), turned, cv::ROTATE_180);
      EXPECT_EQ(cv::norm(turned, drawn, cv::NORM_INF), 0) << dict << " id " << id;
      cv::Mat upright = tag(cv::Rect(1, 1, tag.cols - 2, tag.rows - 2));
      EXPECT_GT(cv::norm(upright, drawn, cv::NORM_INF), 0) << dict << " id " << id;
    }
  }
}

TEST(ArucoAprilTagDictionaries, OfficialTagDecodesWithCornersTwoPositionsOn) {
  constexpr int kCell = 8;
  for (int id : {0, 3, 11}) {
    int border = 0;
    const cv::Mat tag = testing::render_apriltag("tag36h11", id, &border);
    cv::Mat big, image;
    cv::resize(tag, big, cv::Size(), kCell, kCell, cv::INTER_NEAREST);
    cv::copyMakeBorder(big, image, kMargin, kMargin, kMargin, kMargin, cv::BORDER_CONSTANT, 255);
    const double lo = kMargin + kCell - 0.5, hi = kMargin + (1 + border) * kCell - 0.5;
    // TL, TR, BR, BL of the official (apriltag_to_image) tag.
    const std::vector<Vec2> official = {Vec2(lo, lo), Vec2(hi, lo), Vec2(hi, hi), Vec2(lo, hi)};
    const auto found = detect("aruco:DICT_APRILTAG_36h11", image);
    ASSERT_EQ(found.size(), 1u) << id;
    EXPECT_EQ(found[0].id, id);
    // drawMarker's top-left is the official tag's bottom-right, and so on round.
    const std::vector<Vec2> expected = {official[2], official[3], official[0], official[1]};
    expect_corners(found[0], expected, 0.01, "tag36h11 id " + std::to_string(id));
    // libapriltag reports the same physical square in the official order.
    std::vector<Detection> april;
    make_detector("apriltag:tag36h11")->detect(image, april);
    ASSERT_EQ(april.size(), 1u);
    for (int k = 0; k < 4; ++k)
      EXPECT_LT((april[0].corners_px[k] - found[0].corners_px[(k + 2) % 4]).norm(), 0.3);
  }
}

TEST(ArucoFilter, RejectsSliversTinyAndNonConvexQuads) {
  const ArucoOptions options;  // 2 px per cell, side ratio 3
  const int border = 6;        // 4x4 dictionaries
  EXPECT_TRUE(detail::plausible_marker_quad({{0, 0}, {20, 0}, {20, 20}, {0, 20}}, border, options));
  EXPECT_TRUE(detail::plausible_marker_quad({{0, 0}, {34, 2}, {34, 14}, {0, 12}}, border, options));
  // Shortest side 11 px < 12 px (2 px for each of 6 cells).
  EXPECT_FALSE(
      detail::plausible_marker_quad({{0, 0}, {11, 0}, {11, 11}, {0, 11}}, border, options));
  // Sliver: 40 x 12 px, ratio 3.3.
  EXPECT_FALSE(
      detail::plausible_marker_quad({{0, 0}, {40, 0}, {40, 12}, {0, 12}}, border, options));
  // Non-convex (a dart).
  EXPECT_FALSE(
      detail::plausible_marker_quad({{0, 0}, {30, 10}, {60, 0}, {30, 40}}, border, options));
}

TEST(ArucoFilter, QuietZoneSeparatesPrintedMarkersFromBlackSurroundings) {
  const Rendered r = render("DICT_4X4_50", 2, 5);
  EXPECT_DOUBLE_EQ(detail::quiet_zone_fraction(r.image, r.corners, 6), 1.0);
  // The same black square pasted on black: no margin cell is brighter than the border.
  cv::Mat dark = cv::Mat::zeros(r.image.size(), CV_8U);
  const cv::Rect square(kMargin, kMargin, 6 * 5, 6 * 5);
  r.image(square).copyTo(dark(square));
  EXPECT_DOUBLE_EQ(detail::quiet_zone_fraction(dark, r.corners, 6), 0.0);
  EXPECT_EQ(detect("aruco:DICT_4X4_50", r.image).size(), 1u);
  EXPECT_EQ(detect("aruco:DICT_4X4_50", dark).size(), 0u);
}

TEST(ArucoRegistry, ListsEveryPredefinedDictionaryWithItsLayout) {
  const auto families = known_families();
  const auto aruco = std::count_if(families.begin(), families.end(),
                                   [](const std::string& f) { return f.rfind("aruco:", 0) == 0; });
  EXPECT_EQ(aruco, 21);
  EXPECT_NE(std::find(families.begin(), families.end(), "aruco:DICT_APRILTAG_36h11"),
            families.end());
  EXPECT_EQ(family_layout("aruco:DICT_4X4_50").border_width, 6);
  EXPECT_EQ(family_layout("aruco:DICT_4X4_50").total_width, 8);
  EXPECT_EQ(family_layout("aruco:DICT_ARUCO_ORIGINAL").border_width, 7);
  // The same square as the AprilTag family of the same name.
  EXPECT_EQ(family_layout("aruco:DICT_APRILTAG_36h11").border_width,
            family_layout("apriltag:tag36h11").border_width);
  EXPECT_EQ(family_layout("aruco:DICT_APRILTAG_36h11").total_width,
            family_layout("apriltag:tag36h11").total_width);
}

TEST(ArucoRegistry, RejectsUnknownDictionariesAndBadOptions) {
  EXPECT_THROW(make_detector("aruco:DICT_9X9_50"), InputError);
  try {
    make_detector("DICT_4X4_50");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("aruco:DICT_4X4_50"), std::string::npos) << e.what();
  }
  DetectorOptions bad;
  bad.aruco.window_min = 1;
  EXPECT_THROW(make_detector("aruco:DICT_4X4_50", bad), InputError);
  bad = {};
  bad.aruco.error_correction_rate = 2;
  EXPECT_THROW(make_detector("aruco:DICT_4X4_50", bad), InputError);
  bad = {};
  bad.aruco.min_quiet_zone = 1.5;
  EXPECT_THROW(make_detector("aruco:DICT_4X4_50", bad), InputError);
}

}  // namespace
}  // namespace iilfm
