#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/aruco.hpp>
#include <opencv2/imgproc.hpp>

#include "../../src/detectors/search_regions.hpp"
#include "apriltag_render.hpp"
#include "iilfm/detector.hpp"

namespace iilfm {
namespace {

using detail::is_binary;
using detail::search_regions;
using detail::SearchRegionRules;

// A marker of `family` ("apriltag:tag36h11", "aruco:DICT_4X4_50"), one pixel per cell, with a
// one-cell white margin.
cv::Mat render(const std::string& family, int id) {
  const std::string name = family.substr(family.find(':') + 1);
  if (family.rfind("apriltag:", 0) == 0) return testing::render_apriltag(name, id);
  const int dictionary = name == "DICT_4X4_50" ? cv::aruco::DICT_4X4_50 : cv::aruco::DICT_6X6_250;
  const cv::Ptr<cv::aruco::Dictionary> d = cv::aruco::getPredefinedDictionary(dictionary);
  cv::Mat marker, padded;
  d->drawMarker(id, d->markerSize + 2, marker, 1);
  cv::copyMakeBorder(marker, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, 255);
  return padded;
}

// A marker warped by the homography taking its unit square to `quad` (nearest neighbour, so the
// canvas stays binary), drawn on `canvas`.
void draw_tag(cv::Mat& canvas, const std::string& family, int id,
              const std::vector<cv::Point2f>& quad) {
  const cv::Mat tag = render(family, id);
  const float n = static_cast<float>(tag.cols);
  const std::vector<cv::Point2f> unit{{0, 0}, {n, 0}, {n, n}, {0, n}};
  const cv::Mat h = cv::getPerspectiveTransform(unit, quad);
  cv::Mat warped;
  cv::warpPerspective(tag, warped, h, canvas.size(), cv::INTER_NEAREST, cv::BORDER_CONSTANT, 128);
  // Where the tag (white margin included) lands, it replaces the canvas.
  warped.copyTo(canvas, warped != 128);
}

std::vector<cv::Point2f> square(float x, float y, float side, float angle_deg = 0) {
  const float c = std::cos(angle_deg * static_cast<float>(CV_PI) / 180);
  const float s = std::sin(angle_deg * static_cast<float>(CV_PI) / 180);
  std::vector<cv::Point2f> out;
  for (const cv::Point2f& p :
       {cv::Point2f(-1, -1), cv::Point2f(1, -1), cv::Point2f(1, 1), cv::Point2f(-1, 1)})
    out.emplace_back(x + side / 2 * (c * p.x - s * p.y), y + side / 2 * (s * p.x + c * p.y));
  return out;
}

// A LiDAR-like scene: white wall, black floor touching the image's bottom and sides with ring
// steps, a long dark sliver (a cable, a shelf edge), and tags of several sizes, angles and
// perspectives.
cv::Mat scene(const std::string& family) {
  cv::Mat image(300, 1600, CV_8U, cv::Scalar(255));
  for (int x = 0; x < image.cols; x += 80)  // a staircase floor line
    image(cv::Rect(x, 230 + (x / 80) % 3 * 12, 80, 70 - (x / 80) % 3 * 12)).setTo(0);
  image(cv::Rect(1100, 100, 400, 6)).setTo(0);
  draw_tag(image, family, 0, square(150, 100, 120));
  draw_tag(image, family, 1, square(400, 110, 70, 25));
  draw_tag(image, family, 2, {{600, 60}, {720, 80}, {715, 170}, {605, 185}});
  draw_tag(image, family, 3, square(900, 120, 44, -40));
  return image;
}

TEST(IsBinary, AcceptsOnlyImagesOfZeroAnd255) {
  cv::Mat image(7, 33, CV_8U, cv::Scalar(255));
  image(cv::Rect(3, 2, 10, 4)).setTo(0);
  EXPECT_TRUE(is_binary(image));
  for (int value : {1, 127, 128, 254}) {
    cv::Mat other = image.clone();
    other.at<std::uint8_t>(6, 32) = static_cast<std::uint8_t>(value);
    EXPECT_FALSE(is_binary(other)) << value;
  }
}

TEST(SearchRegions, CoverTheTagsAndLeaveTheFloorAndTheSliverOut) {
  const cv::Mat image = scene("apriltag:tag36h11");
  const std::vector<cv::Rect> regions = search_regions(image, SearchRegionRules{});
  ASSERT_FALSE(regions.empty());
  double area = 0;
  for (const cv::Rect& r : regions) area += r.area();
  EXPECT_LT(area, 0.35 * static_cast<double>(image.total())) << regions.size() << " regions";
  auto covered = [&](cv::Rect box) {
    return std::any_of(regions.begin(), regions.end(),
                       [&](const cv::Rect& r) { return (r & box) == box; });
  };
  // Each tag with its white margin lies whole in one region.
  for (const cv::Rect& tag : {cv::Rect(90, 40, 120, 120), cv::Rect(355, 65, 90, 90),
                              cv::Rect(600, 60, 120, 125), cv::Rect(870, 90, 60, 60)})
    EXPECT_TRUE(covered(tag)) << tag;
  // Nothing around the sliver, nor along the floor away from the tags.
  for (const cv::Rect& r : regions) {
    EXPECT_EQ((r & cv::Rect(1100, 100, 400, 6)).area(), 0) << r;
    EXPECT_EQ((r & cv::Rect(1100, 260, 500, 40)).area(), 0) << r;
  }
  // Regions are disjoint and start on libapriltag's 4-pixel tiles.
  for (std::size_t i = 0; i < regions.size(); ++i) {
    EXPECT_EQ(regions[i].x % 4, 0);
    EXPECT_EQ(regions[i].y % 4, 0);
    for (std::size_t j = i + 1; j < regions.size(); ++j)
      EXPECT_EQ((regions[i] & regions[j]).area(), 0);
  }
}

// A far marker on a Livox image: its black square's outline notched by holes and blurred cells, so
// the outline simplifies to far more than 12 corners; its convex hull is still a quad.
TEST(SearchRegions, ARaggedSquareIsSearchedThroughItsHull) {
  cv::Mat image(120, 240, CV_8U, cv::Scalar(255));
  const cv::Rect square_box(60, 40, 34, 34);
  image(square_box).setTo(0);
  cv::RNG rng(11);
  for (int k = 2; k < 30; k += 4) {  // notches 2-7 pixels deep into every side
    const int depth = rng.uniform(2, 8), at = square_box.x + k;
    image(cv::Rect(at, square_box.y, 2, depth)).setTo(255);
    image(cv::Rect(at, square_box.br().y - depth, 2, depth)).setTo(255);
    image(cv::Rect(square_box.x, square_box.y + k, depth, 2)).setTo(255);
    image(cv::Rect(square_box.br().x - depth, square_box.y + k, depth, 2)).setTo(255);
  }
  const auto covered = [&](const std::vector<cv::Rect>& regions) {
    return std::any_of(regions.begin(), regions.end(),
                       [&](const cv::Rect& r) { return (r & square_box) == square_box; });
  };
  EXPECT_TRUE(covered(search_regions(image, SearchRegionRules{})));
  SearchRegionRules outline_only;
  outline_only.max_hull_vertices = 0;
  EXPECT_FALSE(covered(search_regions(image, outline_only)));  // what the hull rule adds
}

TEST(SearchRegions, ABusyImageIsSearchedWhole) {
  cv::Mat image(200, 200, CV_8U);
  cv::RNG rng(7);
  for (int y = 0; y < image.rows; y += 5)
    for (int x = 0; x < image.cols; x += 5)
      image(cv::Rect(x, y, 5, 5)).setTo(rng.uniform(0, 2) * 255);
  const std::vector<detail::SearchRegion> regions =
      detail::sized_search_regions(image, SearchRegionRules{});
  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].box, cv::Rect(0, 0, 200, 200));
  EXPECT_EQ(regions[0].least_outer_side_px, 0);  // not traced: no outline known
}

TEST(SearchRegions, AMarkerFillingTheImageIsSearchedWhole) {
  // Few boundaries, but the one region would cover most of the image: one call does it.
  cv::Mat image(240, 320, CV_8U, cv::Scalar(255));
  draw_tag(image, "apriltag:tag36h11", 7, square(160, 120, 200));
  const std::vector<detail::SearchRegion> regions =
      detail::sized_search_regions(image, SearchRegionRules{});
  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].box, cv::Rect(0, 0, 320, 240));
  // Its outlines were traced: the black square's 160 px side, so libapriltag may halve it.
  EXPECT_NEAR(regions[0].least_outer_side_px, 160, 2);
  std::vector<Detection> found;
  make_detector("apriltag:tag36h11")->detect(image, found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 7);
}

// The strip across a full-circle image's seam: only what crosses its middle column is wanted, and
// a busy strip is still traced rather than searched whole.
TEST(SearchRegions, OnlyBoundariesNearTheCrossingColumnAreSearchedEvenInABusyImage) {
  cv::Mat image = scene("apriltag:tag36h11");
  cv::RNG rng(3);
  for (int y = 0; y < 200; y += 5)  // clutter right of the tags, busy enough to search whole
    for (int x = 1000; x < 1600; x += 5) image(cv::Rect(x, y, 5, 5)).setTo(rng.uniform(0, 2) * 255);
  ASSERT_EQ(search_regions(image, SearchRegionRules{}).size(), 1u);  // the whole image
  SearchRegionRules rules;
  rules.crossing_column = 400;  // through tag 1 (centre 400, 70 px, turned 25 degrees)
  const std::vector<cv::Rect> regions = search_regions(image, rules);
  ASSERT_FALSE(regions.empty());
  const cv::Rect tag1(355, 65, 90, 90);
  EXPECT_TRUE(std::any_of(regions.begin(), regions.end(),
                          [&](const cv::Rect& r) { return (r & tag1) == tag1; }));
  for (const cv::Rect& r : regions) {
    EXPECT_LE(r.x, 400) << r;
    EXPECT_GT(r.br().x, 400) << r;
  }
  std::vector<Detection> found;
  DetectorImages images{image, cv::Mat(), cv::Mat()};
  images.crossing_column = 400;
  make_detector("apriltag:tag36h11")->detect_images(images, found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].id, 1);
}

TEST(SearchRegions, AnImageWithoutBoundariesHasNone) {
  EXPECT_TRUE(search_regions(cv::Mat(50, 80, CV_8U, cv::Scalar(255)), {}).empty());
  EXPECT_TRUE(search_regions(cv::Mat(50, 80, CV_8U, cv::Scalar(0)), {}).empty());
}

// The detectors searching regions find what they find on the whole image, for families with the
// data inside the border and outside it (tagStandard41h12 reads bits two cells beyond its quad),
// and for ArUco (adaptive thresholds over windows up to 23 pixels).
class SearchRegionFamilies : public ::testing::TestWithParam<std::string> {};

TEST_P(SearchRegionFamilies, FindTheMarkersOfTheWholeImage) {
  const std::string family = GetParam();
  const cv::Mat image = scene(family);
  std::vector<Detection> in_regions, whole;
  DetectorOptions options;
  options.apriltag.half_resolution_px_per_cell = 0;  // every region at full resolution
  make_detector(family, options)->detect(image, in_regions);
  options.apriltag.search_regions = options.aruco.search_regions = false;
  make_detector(family, options)->detect(image, whole);
  ASSERT_EQ(whole.size(), 4u) << family;
  ASSERT_EQ(in_regions.size(), whole.size()) << family;
  auto by_id = [](const Detection& a, const Detection& b) { return a.id < b.id; };
  std::sort(in_regions.begin(), in_regions.end(), by_id);
  std::sort(whole.begin(), whole.end(), by_id);
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(in_regions[i].id, whole[i].id);
    EXPECT_EQ(in_regions[i].hamming, whole[i].hamming);
    // libapriltag's quad fit works in floats from the image origin: moving the origin moves
    // corners by rounding alone (measured up to 0.1 px on LiDAR images, 0 here).
    for (int k = 0; k < 4; ++k)
      EXPECT_LT((in_regions[i].corners_px[k] - whole[i].corners_px[k]).norm(), 0.15)
          << family << " id " << whole[i].id << " corner " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Families, SearchRegionFamilies,
                         ::testing::Values("apriltag:tag36h11", "apriltag:tag16h5",
                                           "apriltag:tag25h9", "apriltag:tagStandard41h12",
                                           "apriltag:tagCustom48h12", "aruco:DICT_4X4_50",
                                           "aruco:DICT_6X6_250"));

// Each region knows the shorter side of its smallest outermost outline: the tags' black squares,
// not the cells inside them.
TEST(SearchRegions, ARegionKnowsTheSmallestOutlineThatNoOtherHolds) {
  const cv::Mat image = scene("apriltag:tag36h11");
  const std::vector<detail::SearchRegion> regions =
      detail::sized_search_regions(image, SearchRegionRules{});
  const auto least_side_around = [&](cv::Point centre) {
    for (const detail::SearchRegion& r : regions)
      if (r.box.contains(centre)) return r.least_outer_side_px;
    return -1;
  };
  // Tag 0: 120 px with its one-cell margin, so a 96 px black square (and 12 px cells inside it).
  EXPECT_NEAR(least_side_around({150, 100}), 96, 2);
  // Tag 3: 44 px turned by 40 degrees, a 35 px black square (its upright box: 50 px).
  EXPECT_NEAR(least_side_around({900, 120}), 35, 2);
}

// Where every outline of a region spans half_resolution_px_per_cell pixels a cell (tags 0, 1 and 2
// here, 7-12 px a cell; not tag 3, 4.4), libapriltag finds the quads at half resolution. The same
// markers come out, their corners within a quarter pixel of the full resolution's (edges are
// refined at full resolution).
TEST(SearchRegionDetector, LargeOutlinesFoundAtHalfResolutionKeepTheirCorners) {
  for (const std::string family : {"apriltag:tag36h11", "apriltag:tag25h9"}) {
    const cv::Mat image = scene(family);
    DetectorOptions options;
    std::vector<Detection> half, full;
    make_detector(family, options)->detect(image, half);
    options.apriltag.half_resolution_px_per_cell = 0;
    make_detector(family, options)->detect(image, full);
    ASSERT_EQ(full.size(), 4u) << family;
    ASSERT_EQ(half.size(), full.size()) << family;
    const auto by_id = [](const Detection& a, const Detection& b) { return a.id < b.id; };
    std::sort(half.begin(), half.end(), by_id);
    std::sort(full.begin(), full.end(), by_id);
    double moved = 0;
    for (std::size_t i = 0; i < full.size(); ++i) {
      EXPECT_EQ(half[i].id, full[i].id);
      for (int k = 0; k < 4; ++k)
        moved = std::max(moved, (half[i].corners_px[k] - full[i].corners_px[k]).norm());
    }
    EXPECT_LT(moved, 0.3) << family;  // measured 0.25 (tag36h11)
    EXPECT_GT(moved, 0.0) << family;  // some region was searched at half resolution
  }
}

TEST(SearchRegionDetector, AGrayImageIsSearchedWhole) {
  // A dark-gray tag on a light-gray wall: no pixel is 0, so a region search would see one
  // foreground and no boundary; only libapriltag's own local threshold finds the tag.
  cv::Mat image = scene("apriltag:tag36h11");
  image.setTo(60, image == 0);
  image.setTo(200, image == 255);
  std::vector<Detection> found;
  make_detector("apriltag:tag36h11")->detect(image, found);
  EXPECT_EQ(found.size(), 4u);
}

}  // namespace
}  // namespace iilfm
