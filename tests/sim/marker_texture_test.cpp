// AprilTag textures come from libapriltag with the geometry the simulator relies on (ArUco:
// aruco_texture_test.cpp).
#include "iilfm/sim/marker_texture.hpp"

#include <gtest/gtest.h>

#include "iilfm/error.hpp"

namespace iilfm::sim {
namespace {

TEST(MarkerTexture, Tag36h11HasAWhiteQuietZoneAroundABlackBorder) {
  const MarkerTexture t = render_marker_texture("apriltag:tag36h11", 0);
  ASSERT_EQ(t.total_width, 10);
  ASSERT_EQ(t.width_at_border, 8);
  ASSERT_EQ(t.pixels.size(), 100u);
  for (int i = 0; i < 10; ++i) {
    EXPECT_FALSE(t.is_black(0, i));
    EXPECT_FALSE(t.is_black(9, i));
    EXPECT_FALSE(t.is_black(i, 0));
    EXPECT_FALSE(t.is_black(i, 9));
  }
  for (int i = 1; i < 9; ++i) {
    EXPECT_TRUE(t.is_black(1, i));
    EXPECT_TRUE(t.is_black(8, i));
    EXPECT_TRUE(t.is_black(i, 1));
    EXPECT_TRUE(t.is_black(i, 8));
  }
}

TEST(MarkerTexture, EveryShippedFamilyRendersItsFirstAndLastId) {
  const std::vector<std::string> families = apriltag_family_names();
  EXPECT_EQ(families.size(), 9u);
  for (const std::string& family : families) {
    const MarkerTexture t = render_marker_texture(family, 0);
    EXPECT_GT(t.total_width, t.width_at_border) << family;
    EXPECT_EQ(t.pixels.size(), static_cast<std::size_t>(t.total_width * t.total_width)) << family;
  }
  EXPECT_EQ(render_marker_texture("apriltag:tag16h5", 29).total_width, 8);
  EXPECT_EQ(render_marker_texture("apriltag:tagStandard41h12", 0).width_at_border, 5);
}

TEST(MarkerTexture, DistinctIdsPrintDistinctPatterns) {
  EXPECT_NE(render_marker_texture("apriltag:tag36h11", 0).pixels,
            render_marker_texture("apriltag:tag36h11", 1).pixels);
}

TEST(MarkerTexture, UnknownFamiliesAndIdsAreInputErrors) {
  EXPECT_THROW(render_marker_texture("tag36h11", 0), InputError);
  EXPECT_THROW(render_marker_texture("apriltag:tag99h9", 0), InputError);
  EXPECT_THROW(render_marker_texture("apriltag:tag16h5", 30), InputError);
  EXPECT_THROW(render_marker_texture("apriltag:tag36h11", -1), InputError);
}

}  // namespace
}  // namespace iilfm::sim
