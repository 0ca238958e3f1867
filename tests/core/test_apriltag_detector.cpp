#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "../../src/detectors/apriltag_detector.hpp"
#include "apriltag_render.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"

namespace iilfm {
namespace {

constexpr int kCell = 12;    // pixels per tag cell
constexpr int kMargin = 40;  // white pixels around the rendered tag

struct Rendered {
  cv::Mat image;
  std::vector<Vec2> corners;  // expected TL, TR, BR, BL of the black square (centres at integers)
};

Rendered render(const std::string& family, int id) {
  int border = 0;
  const cv::Mat tag = testing::render_apriltag(family, id, &border);
  cv::Mat big;
  cv::resize(tag, big, cv::Size(), kCell, kCell, cv::INTER_NEAREST);
  Rendered out;
  cv::copyMakeBorder(big, out.image, kMargin, kMargin, kMargin, kMargin, cv::BORDER_CONSTANT, 255);
  // The black square spans cells [off, off + border); its edges lie between pixels, i.e. at
  // pixel coordinate (edge index - 0.5) with centres at integers.
  const double off = (tag.cols - border) / 2.0;
  const double lo = kMargin + off * kCell - 0.5, hi = kMargin + (off + border) * kCell - 0.5;
  out.corners = {Vec2(lo, lo), Vec2(hi, lo), Vec2(hi, hi), Vec2(lo, hi)};
  return out;
}

// libapriltag places hard black/white steps about 0.1 px up-left of the true edge (measured:
// -0.10..-0.125 px per axis for 4-12 px cells); on a smoothed edge the mean offset is ~0, which
// pins the half-pixel convention. A convention slip would shift every corner by 0.5 px per axis.
void expect_corners(const Detection& d, const std::vector<Vec2>& expected, double tol,
                    const std::string& what, double mean_tol = 0.2) {
  ASSERT_EQ(d.corners_px.size(), 4u) << what;
  Vec2 mean_offset = Vec2::Zero();
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((d.corners_px[k] - expected[k]).norm(), tol)
        << what << " corner " << k << ": got " << d.corners_px[k].transpose() << " expected "
        << expected[k].transpose();
    mean_offset += (d.corners_px[k] - expected[k]) / 4;
  }
  EXPECT_LT(mean_offset.norm(), mean_tol) << what << " mean offset " << mean_offset.transpose();
}

class AprilTagFamilies : public ::testing::TestWithParam<std::string> {};

TEST_P(AprilTagFamilies, CornersComeInCanonicalOrderAtTheRightPixelCentres) {
  const std::string family = GetParam();
  const Rendered r = render(family, 3);
  auto detector = make_detector("apriltag:" + family);
  std::vector<Detection> found;
  detector->detect(r.image, found);
  ASSERT_EQ(found.size(), 1u) << family;
  EXPECT_EQ(found[0].id, 3);
  EXPECT_EQ(found[0].family, "apriltag:" + family);
  EXPECT_EQ(found[0].hamming, 0);
  // A rotated order would be off by a whole tag side; libapriltag's own corner error on a
  // perfect binary image reaches about 0.25 px on single corners.
  expect_corners(found[0], r.corners, 0.3, family);
}

TEST_P(AprilTagFamilies, OrderFollowsThePrintedTagWhenTheImageIsRotated) {
  const std::string family = GetParam();
  const Rendered r = render(family, 5);
  cv::Mat rotated;
  cv::rotate(r.image, rotated, cv::ROTATE_90_CLOCKWISE);
  // Rotating clockwise maps (x, y) to (H - 1 - y, x): the printed top-left goes to the top-right.
  const double n = r.image.rows - 1;
  std::vector<Vec2> expected;
  for (const Vec2& c : r.corners) expected.emplace_back(n - c.y(), c.x());
  std::vector<Detection> found;
  make_detector("apriltag:" + family)->detect(rotated, found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 5);
  expect_corners(found[0], expected, 0.3, family + " rotated");
  EXPECT_GT(found[0].corners_px[0].x(), found[0].corners_px[3].x());  // TL is now right of BL
}

TEST(AprilTagDetector, SmoothedEdgesPinTheHalfPixelConvention) {
  Rendered r = render("tag36h11", 3);
  cv::GaussianBlur(r.image, r.image, cv::Size(0, 0), 1.5);
  std::vector<Detection> found;
  make_detector("apriltag:tag36h11")->detect(r.image, found);
  ASSERT_EQ(found.size(), 1u);
  expect_corners(found[0], r.corners, 0.3, "blurred", 0.05);
}

INSTANTIATE_TEST_SUITE_P(AllFamilies, AprilTagFamilies,
                         ::testing::Values("tag16h5", "tag25h9", "tag36h10", "tag36h11",
                                           "tagCircle21h7", "tagCircle49h12", "tagCustom48h12",
                                           "tagStandard41h12", "tagStandard52h13"));

TEST(AprilTagDetector, MirroredTagDoesNotDecodeAsItself) {
  const Rendered r = render("tag36h11", 0);
  cv::Mat mirrored;
  cv::flip(r.image, mirrored, 1);
  std::vector<Detection> found;
  make_detector("apriltag:tag36h11")->detect(mirrored, found);
  for (const Detection& d : found) EXPECT_NE(d.id, 0);
}

// Bits corrected by default (docs/pipeline.md): (h - 1) / 2 - 2, at most 2 (1 for families of
// more than 5000 codes), fewer while a random quad would decode more often than once in 5000.
TEST(AprilTagDetector, DefaultCorrectionKeepsChanceMatchesRare) {
  using detail::default_max_hamming;
  EXPECT_EQ(default_max_hamming(11, 587, 36), 2);    // tag36h11: 2.3e-5 at 2 bits
  EXPECT_EQ(default_max_hamming(10, 2320, 36), 2);   // tag36h10: 9.0e-5
  EXPECT_EQ(default_max_hamming(12, 2115, 41), 2);   // tagStandard41h12
  EXPECT_EQ(default_max_hamming(13, 48714, 52), 1);  // tagStandard52h13: the table's size
  EXPECT_EQ(default_max_hamming(9, 35, 25), 1);      // tag25h9: 1.4e-3 at 2 bits, 1.1e-4 at 1
  EXPECT_EQ(default_max_hamming(7, 38, 21), 0);      // tagCircle21h7: 1.6e-3 at 1 bit
  EXPECT_EQ(default_max_hamming(5, 30, 16), 0);      // tag16h5
}

// The chance bound that also decides which readings of gray pixels are kept (docs/detectors.md):
// tag16h5 is above it even read without error, so its gray readings never are.
TEST(AprilTagDetector, ChanceMatchOfTheWeakAndStrongFamilies) {
  using detail::chance_match;
  EXPECT_NEAR(chance_match(30, 16, 0), 4.0 * 30 / 65536, 1e-12);  // tag16h5: 1.8e-3
  EXPECT_GT(chance_match(30, 16, 0), detail::kMaxChanceMatch);
  EXPECT_NEAR(chance_match(587, 36, 2), 4.0 * 587 * (1 + 36 + 630) / std::ldexp(1.0, 36), 1e-12);
  EXPECT_LT(chance_match(587, 36, 2), detail::kMaxChanceMatch);  // tag36h11: 2.3e-5
  EXPECT_GT(chance_match(35, 25, 2), detail::kMaxChanceMatch);   // tag25h9: 1.4e-3 at 2 bits
  EXPECT_LT(chance_match(35, 25, 1), detail::kMaxChanceMatch);   // and 1.1e-4 at 1
}

// The decoding table is shared by every detector of its (family, bits) and outlives them: a tag
// with two wrong bits decodes with 2 bits corrected, not with 0, whichever detector came and went
// before (under AddressSanitizer a freed table would be a use after free).
TEST(AprilTagDetector, SharedDecodingTablesOutliveTheirDetectorsAndKeepTheirBits) {
  int border = 0;
  cv::Mat tag = testing::render_apriltag("tag36h11", 5, &border);
  const int data = (tag.cols - border) / 2 + 1;  // first data cell inside the black border
  for (const cv::Point cell : {cv::Point(data + 1, data + 1), cv::Point(data + 3, data + 2)})
    tag.at<std::uint8_t>(cell) = static_cast<std::uint8_t>(255 - tag.at<std::uint8_t>(cell));
  cv::Mat big, image;
  cv::resize(tag, big, cv::Size(), kCell, kCell, cv::INTER_NEAREST);
  cv::copyMakeBorder(big, image, kMargin, kMargin, kMargin, kMargin, cv::BORDER_CONSTANT, 255);
  const auto ids_found = [&](int max_hamming) {
    DetectorOptions options;
    options.apriltag.max_hamming = max_hamming;
    std::vector<Detection> found;
    make_detector("apriltag:tag36h11", options)->detect(image, found);  // destroyed after
    std::vector<int> ids;
    for (const Detection& d : found) ids.push_back(d.id);
    return ids;
  };
  EXPECT_EQ(ids_found(2), std::vector<int>{5});
  EXPECT_EQ(ids_found(0), std::vector<int>{});
  EXPECT_EQ(ids_found(2), std::vector<int>{5});
  EXPECT_EQ(ids_found(-1), std::vector<int>{5});  // the default for tag36h11 is 2
  EXPECT_EQ(ids_found(0), std::vector<int>{});
}

TEST(DetectorRegistry, RejectsUnknownFamiliesWithAHint) {
  try {
    make_detector("tag36h11");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("apriltag:tag36h11"), std::string::npos) << e.what();
  }
  EXPECT_THROW(make_detector("apriltag:tag99h9"), InputError);
  EXPECT_THROW(make_detector("quirk:tag36h11"), InputError);
  const std::vector<std::string> families = known_families();
  int apriltag_families = 0;
  for (const std::string& f : families) apriltag_families += f.rfind("apriltag:", 0) == 0;
  EXPECT_EQ(apriltag_families, 9);
  EXPECT_EQ(family_layout("apriltag:tag36h11").border_width, 8);
  EXPECT_EQ(family_layout("apriltag:tag36h11").total_width, 10);
}

}  // namespace
}  // namespace iilfm
