// One report per physical marker: overlapping detections of different families are merged.
#include <gtest/gtest.h>

#include "iilfm/duplicates.hpp"

namespace iilfm {
namespace {

Detection square(const std::string& family, int id, double x, double y, double side) {
  Detection d;
  d.family = family;
  d.id = id;
  d.corners_px = {{x, y}, {x + side, y}, {x + side, y + side}, {x, y + side}};
  return d;
}

TEST(Duplicates, OverlapIsIntersectionOverUnionWhateverTheCornerOrder) {
  const Detection a = square("apriltag:tag36h11", 0, 0, 0, 10);
  Detection b = square("aruco:DICT_APRILTAG_36h11", 0, 5, 0, 10);  // half overlapping
  EXPECT_NEAR(outline_overlap(a, b), 50.0 / 150.0, 1e-6);
  std::reverse(b.corners_px.begin(), b.corners_px.end());  // counter-clockwise
  EXPECT_NEAR(outline_overlap(a, b), 50.0 / 150.0, 1e-6);
  // ArUco's AprilTag dictionaries report the same tag's corners two positions on.
  Detection turned = a;
  std::rotate(turned.corners_px.begin(), turned.corners_px.begin() + 2, turned.corners_px.end());
  EXPECT_NEAR(outline_overlap(a, turned), 1.0, 1e-6);
  EXPECT_EQ(outline_overlap(a, square("x:y", 0, 20, 0, 10)), 0.0);
}

TEST(Duplicates, TheFamilyListedFirstStaysUnlessOnlyTheOtherIsPreferred) {
  std::vector<Detection> d = {square("apriltag:tag36h11", 3, 0, 0, 40),
                              square("apriltag:tag36h11", 4, 100, 0, 40),
                              square("aruco:DICT_APRILTAG_36h11", 3, 0.4, 0.3, 40),
                              square("aruco:DICT_4X4_50", 1, 200, 0, 40)};
  std::vector<Detection> merged = d;
  EXPECT_EQ(drop_duplicate_detections(merged), 1u);
  ASSERT_EQ(merged.size(), 3u);
  EXPECT_EQ(merged[0].family, "apriltag:tag36h11");
  EXPECT_EQ(merged[0].id, 3);
  EXPECT_EQ(merged[1].id, 4);
  EXPECT_EQ(merged[2].family, "aruco:DICT_4X4_50");

  merged = d;
  const auto in_map = [](const Detection& x) { return x.family.rfind("aruco:", 0) == 0; };
  EXPECT_EQ(drop_duplicate_detections(merged, in_map), 1u);
  ASSERT_EQ(merged.size(), 3u);
  EXPECT_EQ(merged[0].id, 4);
  EXPECT_EQ(merged[1].family, "aruco:DICT_APRILTAG_36h11");
}

TEST(Duplicates, SameFamilyAndSmallOverlapsAreKept) {
  // Two decodings of one family are the back-end's business; a small marker inside a big one's
  // quiet zone overlaps it by less than half.
  std::vector<Detection> d = {square("apriltag:tag36h11", 1, 0, 0, 40),
                              square("apriltag:tag36h11", 2, 1, 1, 40),
                              square("aruco:DICT_4X4_50", 7, 10, 10, 20)};
  EXPECT_EQ(drop_duplicate_detections(d), 0u);
  EXPECT_EQ(d.size(), 3u);
}

}  // namespace
}  // namespace iilfm
