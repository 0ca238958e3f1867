#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "iilfm/error.hpp"
#include "iilfm/marker_map.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm {
namespace {

std::string write_temp(const std::string& name, const std::string& text) {
  const auto path = iilfm::testing::process_scratch_dir() / ("map_" + name + ".yaml");
  std::ofstream(path) << text;
  return path.string();
}

// The paper's set-up: tag 0 of 164 mm on the plane x = 3.62 m facing the LiDAR (-x).
const char* kPaperMap = R"(markers:
  - family: apriltag:tag36h11
    id: 0
    corners:
      - [3.62,  0.082, 0.567]
      - [3.62, -0.082, 0.567]
      - [3.62, -0.082, 0.403]
      - [3.62,  0.082, 0.403]
)";

std::string load_error(const std::string& name, const std::string& text) {
  const std::string path = write_temp(name, text);
  try {
    MarkerMap::load(path);
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    return message;
  }
  ADD_FAILURE() << "no error for " << name;
  return "";
}

TEST(MarkerMap, LoadsCornerForm) {
  const MarkerMap map = MarkerMap::load(write_temp("corners", kPaperMap));
  ASSERT_EQ(map.markers().size(), 1u);
  const MapMarker* m = map.find("apriltag:tag36h11", 0);
  ASSERT_NE(m, nullptr);
  EXPECT_NEAR(m->size, 0.164, 1e-12);
  EXPECT_EQ(m->corners_world[2], Vec3(3.62, -0.082, 0.403));
  EXPECT_EQ(map.find("apriltag:tag36h11", 1), nullptr);
  EXPECT_EQ(map.find("apriltag:tag25h9", 0), nullptr);
}

TEST(MarkerMap, SizeAndPoseFormsGiveTheSameCorners) {
  // Marker frame: z out of the face towards the LiDAR (-x world), x to the marker's right (-y),
  // y up (+z): rotation columns (0,-1,0), (0,0,1), (-1,0,0) = rpy (90, 0, -90) deg.
  const MarkerMap rpy = MarkerMap::load(write_temp("rpy", R"(markers:
  - family: apriltag:tag36h11
    id: 0
    size: 0.164
    pose: {position: [3.62, 0, 0.485], rpy_deg: [90, 0, -90]}
)"));
  const MarkerMap quat = MarkerMap::load(write_temp("quat", R"(markers:
  - family: apriltag:tag36h11
    id: 0
    size: 0.164
    pose: {position: [3.62, 0, 0.485], quat_xyzw: [0.5, -0.5, -0.5, 0.5]}
)"));
  const MarkerMap corners = MarkerMap::load(write_temp("corners2", kPaperMap));
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((rpy.markers()[0].corners_world[k] - corners.markers()[0].corners_world[k]).norm(),
              1e-9)
        << "corner " << k;
    EXPECT_LT((quat.markers()[0].corners_world[k] - corners.markers()[0].corners_world[k]).norm(),
              1e-9)
        << "corner " << k;
  }
}

TEST(MarkerMap, RejectsBadMarkersNamingThem) {
  EXPECT_NE(load_error("count", R"(markers:
  - {family: apriltag:tag36h11, id: 3, corners: [[0,0,0],[1,0,0],[1,1,0]]}
)")
                .find("marker #1"),
            std::string::npos);
  EXPECT_NE(load_error("planar", R"(markers:
  - {family: apriltag:tag36h11, id: 4, corners: [[0,1,1],[0,0,1],[0,0,0],[0.05,1,0]]}
)")
                .find("not planar"),
            std::string::npos);
  EXPECT_NE(load_error("square", R"(markers:
  - {family: apriltag:tag36h11, id: 5, corners: [[0,2,1],[0,0,1],[0,0,0],[0,2,0]]}
)")
                .find("not a square"),
            std::string::npos);
  EXPECT_NE(load_error("order", R"(markers:
  - {family: apriltag:tag36h11, id: 6, corners: [[0,1,1],[0,0,0],[0,0,1],[0,1,0]]}
)")
                .find("not a square"),
            std::string::npos);
  const std::string dup = load_error("dup", R"(markers:
  - {family: apriltag:tag36h11, id: 7, size: 0.1, pose: {position: [1,0,0], rpy_deg: [0,0,0]}}
  - {family: apriltag:tag36h11, id: 7, size: 0.1, pose: {position: [2,0,0], rpy_deg: [0,0,0]}}
)");
  EXPECT_NE(dup.find("apriltag:tag36h11/7"), std::string::npos) << dup;
  EXPECT_NE(dup.find("duplicate"), std::string::npos) << dup;
  EXPECT_NE(load_error("family", R"(markers:
  - {family: apriltag:tag99h1, id: 0, size: 0.1, pose: {position: [1,0,0], rpy_deg: [0,0,0]}}
)")
                .find("tag99h1"),
            std::string::npos);
  const std::string id = load_error("id", R"(markers:
  - {family: aruco:DICT_4X4_50, id: 50, size: 0.1, pose: {position: [1,0,0], rpy_deg: [0,0,0]}}
)");
  EXPECT_NE(id.find("aruco:DICT_4X4_50/50: id not in the family (ids 0..49)"), std::string::npos)
      << id;
  EXPECT_NE(load_error("nopose", R"(markers:
  - {family: apriltag:tag36h11, id: 0, size: 0.1}
)")
                .find("pose"),
            std::string::npos);
  EXPECT_NE(load_error("yaml", "markers: [ {family: x").find("YAML"), std::string::npos);
  EXPECT_NE(load_error("empty", "markers: []\n").find("no markers"), std::string::npos);
  EXPECT_NE(load_error("top", "foo: 1\n").find("markers"), std::string::npos);
}

TEST(MarkerMap, MissingFileIsAnInputError) {
  try {
    MarkerMap::load("/nonexistent/map.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/map.yaml"), std::string::npos);
  }
}

}  // namespace
}  // namespace iilfm
