// YAML scene files: the same scene as built in code, a write/read round trip, the shipped
// examples, and one clear error per mistake.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "iilfm/error.hpp"
#include "iilfm/sim/sim.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm::sim {
namespace {

namespace fs = std::filesystem;
constexpr double kDegToRad = M_PI / 180.0;

void expect_same_pose(const Isometry3& a, const Isometry3& b, const std::string& what) {
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-8) << what;
  EXPECT_LT((a.linear() - b.linear()).norm(), 1e-8) << what << "\n"
                                                    << a.linear() << "\n"
                                                    << b.linear();
}

void expect_same_setup(const SceneSetup& a, const SceneSetup& b) {
  EXPECT_EQ(a.sensor, b.sensor);
  expect_same_pose(a.T_world_lidar, b.T_world_lidar, "lidar");
  EXPECT_FLOAT_EQ(a.scene.white_intensity, b.scene.white_intensity);
  EXPECT_FLOAT_EQ(a.scene.black_intensity, b.scene.black_intensity);
  ASSERT_EQ(a.scene.walls.size(), b.scene.walls.size());
  for (std::size_t i = 0; i < a.scene.walls.size(); ++i) {
    const Wall &wa = a.scene.walls[i], &wb = b.scene.walls[i];
    expect_same_pose(wa.T_world_wall, wb.T_world_wall, "wall " + std::to_string(i));
    EXPECT_NEAR(wa.width_m, wb.width_m, 1e-9) << i;
    EXPECT_NEAR(wa.height_m, wb.height_m, 1e-9) << i;
    EXPECT_FLOAT_EQ(wa.reflectivity, wb.reflectivity) << i;
  }
  ASSERT_EQ(a.scene.markers.size(), b.scene.markers.size());
  for (std::size_t i = 0; i < a.scene.markers.size(); ++i) {
    const MarkerSpec &ma = a.scene.markers[i], &mb = b.scene.markers[i];
    EXPECT_EQ(ma.family, mb.family);
    EXPECT_EQ(ma.id, mb.id);
    EXPECT_NEAR(ma.size_m, mb.size_m, 1e-9);
    expect_same_pose(ma.T_world_marker, mb.T_world_marker, "marker " + std::to_string(i));
  }
}

// The paper's tag wall plus a box, as code builds it.
SceneSetup scene_in_code() {
  SceneSetup s;
  s.scene = wall_scene({wall_marker("apriltag:tag36h11", 0, 0.172, 3.62, 0, 0.485),
                        wall_marker("apriltag:tag25h9", 7, 0.2, 3.62, 1.0, 1.2, 30)},
                       3.62);
  s.scene.white_intensity = 110;
  s.sensor = "vlp16";
  s.T_world_lidar.translation() = Vec3(1.0, 0.5, 0.8);
  s.T_world_lidar.linear() = Eigen::AngleAxisd(10 * kDegToRad, Vec3::UnitZ()).toRotationMatrix();
  return s;
}

// The same scene by hand: wall_scene's wall and floor, markers on the wall and by pose.
const char* kSceneText = R"(
lidar:
  sensor: vlp16
  position: [1.0, 0.5, 0.8]
  rpy_deg: [0, 0, 10]
print: {white: 110}
walls:
  - {centre: [3.62, 0, 1.5], rpy_deg: [90, 0, -90], width: 8, height: 3}
  - {centre: [-1.38, 0, 0], width: 10, height: 8, reflectivity: 25}
markers:
  - {family: "apriltag:tag36h11", id: 0, size: 0.172, on_wall: 0, at: [0, -1.015]}
  - family: apriltag:tag25h9
    id: 7
    size: 0.2
    pose: {position: [3.62, 1.0, 1.2], rpy_deg: [90, -30, -90]}
)";

TEST(SceneFile, HandWrittenYamlGivesTheSceneBuiltInCode) {
  expect_same_setup(parse_scene_yaml(kSceneText, "test.yaml"), scene_in_code());
}

TEST(SceneFile, WriteThenReadGivesTheSameScene) {
  const fs::path path = iilfm::testing::process_scratch_dir() / "scene.yaml";
  SceneSetup original = scene_in_code();
  // A tilted LiDAR and a marker at a general orientation exercise every rpy angle.
  original.T_world_lidar.linear() =
      (Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * Eigen::AngleAxisd(-0.2, Vec3::UnitY()) *
       Eigen::AngleAxisd(0.1, Vec3::UnitX()))
          .toRotationMatrix();
  original.scene.markers[1].T_world_marker.linear() =
      Eigen::AngleAxisd(1.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  write_scene_yaml(path.string(), original);
  expect_same_setup(read_scene_yaml(path.string()), original);
  fs::remove(path);
}

TEST(SceneFile, BoxesBecomeSixFacesAndMarkersSitOnTheWallFront) {
  const SceneSetup s = parse_scene_yaml(R"(
lidar: {sensor: mid40}
walls: [{centre: [0, 3, 1.5], rpy_deg: [90, 0, 0], width: 8, height: 3}]
boxes: [{centre: [2, 1, 0.5], size: [1, 2, 0.6], yaw_deg: 90}]
markers: [{family: "apriltag:tag36h11", id: 4, size: 0.3, on_wall: 0, at: [2, -0.2], angle_deg: 90}]
)",
                                        "box.yaml");
  ASSERT_EQ(s.scene.walls.size(), 7u);
  double top = -1;
  for (std::size_t i = 1; i < 7; ++i)
    top = std::max(top, s.scene.walls[i].T_world_wall.translation().z());
  EXPECT_NEAR(top, 0.8, 1e-12);
  // Yawed 90 deg: the box's 2 m side (local y) now runs along world x, so its two faces across
  // that side are 2 m apart in x.
  double min_x = 1e9, max_x = -1e9;
  for (std::size_t i = 1; i < 7; ++i) {
    min_x = std::min(min_x, s.scene.walls[i].T_world_wall.translation().x());
    max_x = std::max(max_x, s.scene.walls[i].T_world_wall.translation().x());
  }
  EXPECT_NEAR(max_x - min_x, 2.0, 1e-12);
  const MarkerSpec& m = s.scene.markers[0];
  EXPECT_LT((m.T_world_marker.translation() - Vec3(2, 3, 1.3)).norm(), 1e-12);
  // Printed on the front (facing -y), turned 90 deg counter-clockwise: its x axis points up.
  EXPECT_LT((m.T_world_marker.linear().col(2) - Vec3(0, -1, 0)).norm(), 1e-12);
  EXPECT_LT((m.T_world_marker.linear().col(0) - Vec3(0, 0, 1)).norm(), 1e-12);
}

TEST(SceneFile, ArucoMarkersPrintAndRoundTrip) {
  const SceneSetup s = parse_scene_yaml(R"(
lidar: {sensor: vlp16}
walls: [{centre: [2, 0, 0], rpy_deg: [90, 0, -90], width: 4, height: 3}]
markers:
  - {family: "aruco:DICT_ARUCO_ORIGINAL", id: 1023, size: 0.4, on_wall: 0, at: [0, 0]}
  - {family: "aruco:DICT_APRILTAG_36h11", id: 3, size: 0.2, on_wall: 0, at: [1, 0.5]}
)",
                                        "aruco.yaml");
  ASSERT_EQ(s.scene.markers.size(), 2u);
  EXPECT_EQ(s.scene.markers[0].family, "aruco:DICT_ARUCO_ORIGINAL");
  EXPECT_EQ(s.scene.markers[0].id, 1023);
  EXPECT_EQ(s.scene.markers[1].family, "aruco:DICT_APRILTAG_36h11");
  const fs::path path = iilfm::testing::process_scratch_dir() / "aruco_scene.yaml";
  write_scene_yaml(path.string(), s);
  expect_same_setup(read_scene_yaml(path.string()), s);
  fs::remove(path);
}

TEST(SceneFile, ShippedExamplesLoadAndShowTheirMarkers) {
  const std::string dir = std::string(IILFM_SOURCE_DIR) + "/data/scenes/";
  const SceneSetup room = read_scene_yaml(dir + "room.yaml");
  EXPECT_EQ(room.sensor, "avia");
  EXPECT_EQ(room.scene.walls.size(), 6u + 6u);  // 4 walls, floor, ceiling, a box
  ASSERT_EQ(room.scene.markers.size(), 4u);
  SimOptions o;
  o.T_world_lidar = room.T_world_lidar;
  o.frames = 5;
  const SimResult r = simulate(room.scene, sensor_model(room.sensor), o);
  for (const MarkerTruth& m : r.truth.markers) {
    EXPECT_TRUE(m.visible) << "room marker " << m.id;
    EXPECT_GT(m.points_on_marker, 30u) << "room marker " << m.id;
  }

  const SceneSetup around = read_scene_yaml(dir + "around.yaml");
  EXPECT_EQ(around.sensor, "os1-64");
  o.T_world_lidar = around.T_world_lidar;
  o.frames = 1;
  const SimResult a = simulate(around.scene, sensor_model(around.sensor), o);
  ASSERT_EQ(a.truth.markers.size(), 5u);
  for (const MarkerTruth& m : a.truth.markers) {
    EXPECT_TRUE(m.visible) << "around marker " << m.id;
    EXPECT_GT(m.points_on_marker, 20u) << "around marker " << m.id;
  }
}

TEST(SceneFile, ShippedExamplesAreTheNamedScenesRoomAndAround) {
  const std::string dir = std::string(IILFM_SOURCE_DIR) + "/data/scenes/";
  expect_same_setup(read_scene_yaml(dir + "room.yaml"), named_scene("room"));
  expect_same_setup(read_scene_yaml(dir + "around.yaml"), named_scene("around"));
  // Around scales with the distance; room has none to scale.
  const SceneSetup far = named_scene("around", SceneParams{{}, {}, {}, 8.0});
  EXPECT_NEAR(far.scene.walls[0].T_world_wall.translation().x(), 8, 1e-12);
  EXPECT_THROW(named_scene("room", SceneParams{{}, {}, {}, 3.0}), InputError);
}

// The message names the file, the entry and the problem.
void expect_error(const std::string& text, const std::string& where, const std::string& problem) {
  try {
    parse_scene_yaml(text, "bad.yaml");
    ADD_FAILURE() << "expected InputError for:\n" << text;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("bad.yaml: ", 0), 0u) << message;
    EXPECT_NE(message.find(where), std::string::npos) << message;
    EXPECT_NE(message.find(problem), std::string::npos) << message;
  }
}

TEST(SceneFile, EachMistakeGetsItsOwnMessage) {
  const std::string lidar = "lidar: {sensor: mid40}\n";
  const std::string wall =
      "walls: [{centre: [3, 0, 1], rpy_deg: [90, 0, -90], width: 4, height: 2}]\n";
  const std::string tag = "{family: \"apriltag:tag36h11\", id: 0, size: 0.2, ";
  expect_error("walls: [\n  - {", "line", "not valid YAML");
  expect_error("- 1\n- 2\n", "file", "expected a mapping");
  expect_error(wall, "lidar", "needs a 'lidar' entry");
  expect_error("lidar: {position: [0, 0, 0]}\n" + wall, "lidar", "needs 'sensor'");
  expect_error("lidar: {sensor: hdl64}\n" + wall, "lidar", "unknown simulated sensor 'hdl64'");
  expect_error(lidar + "wals: []\n", "file", "unknown key 'wals'");
  expect_error(lidar, "file", "no walls, boxes or markers");
  expect_error(lidar + "walls: {centre: [0, 0, 0]}\n", "walls", "expected a list");
  expect_error(lidar + "walls: [{centre: [0, 0], width: 1, height: 1}]\n", "walls[0]",
               "'centre' must be a list of 3 numbers");
  expect_error(lidar + "walls: [{centre: [0, 0, 0], width: -1, height: 1}]\n", "walls[0]",
               "'width' must be positive");
  expect_error(lidar + "walls: [{centre: [0, 0, 0], width: wide, height: 1}]\n", "walls[0]",
               "'width' must be a number");
  expect_error(lidar + "walls: [{centre: [0, 0, 0], width: 1}]\n", "walls[0]", "needs 'height'");
  expect_error(lidar + "boxes: [{centre: [0, 0, 0], size: [1, 0, 1]}]\n", "boxes[0]",
               "three positive lengths");
  expect_error(lidar + wall + "markers: [" + tag + "on_wall: 1, at: [0, 0]}]\n", "markers[0]",
               "index of one of the 1 walls");
  expect_error(lidar + wall + "markers: [" + tag + "on_wall: 0, at: [2.5, 0]}]\n", "markers[0]",
               "lies off wall 0");
  expect_error(lidar + wall + "markers: [" + tag + "on_wall: 0}]\n", "markers[0]", "needs 'at'");
  expect_error(lidar + wall + "markers: [" + tag + "at: [0, 0]}]\n", "markers[0]",
               "either 'pose' or 'on_wall'");
  expect_error(
      lidar + wall + "markers: [" + tag + "on_wall: 0, at: [0, 0], pose: {position: [0, 0, 0]}}]\n",
      "markers[0]", "either 'pose' or 'on_wall'");
  expect_error(lidar + wall + "markers: [" + tag + "pose: {rpy_deg: [0, 0, 0]}}]\n",
               "markers[0].pose", "needs 'position'");
  expect_error(
      lidar + wall +
          "markers: [{family: \"apriltag:tag36h11\", id: 0, pose: {position: [1, 0, 0]}}]\n",
      "markers[0]", "needs 'size'");
  expect_error(lidar + wall +
                   "markers: [{family: \"apriltag:tag99\", id: 0, size: 0.2, pose: {position: [1, "
                   "0, 0]}}]\n",
               "markers[0]", "tag99");
  expect_error(lidar + wall +
                   "markers: [{family: \"apriltag:tag16h5\", id: 1.5, size: 0.2, pose: {position: "
                   "[1, 0, 0]}}]\n",
               "markers[0]", "whole number");
  expect_error(lidar + wall +
                   "markers: [{family: \"aruco:DICT_4X4_50\", id: 50, size: 0.2, pose: "
                   "{position: [1, 0, 0]}}]\n",
               "markers[0]", "outside aruco:DICT_4X4_50");
  expect_error(lidar + wall +
                   "markers: [{family: \"aruco:DICT_3X3_50\", id: 0, size: 0.2, pose: "
                   "{position: [1, 0, 0]}}]\n",
               "markers[0]", "cannot print marker family 'aruco:DICT_3X3_50'");
  expect_error(
      lidar + wall + "markers: [" + tag + "pose: {position: [1, 0, 0], quat: [0, 0, 0, 1]}}]\n",
      "markers[0].pose", "unknown key 'quat'");
}

TEST(SceneFile, MissingFileNamesThePath) {
  try {
    read_scene_yaml("/nonexistent/room.yaml");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/room.yaml: cannot open"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace iilfm::sim
