// Ground truth corners, visibility, the JSON file and the marker map.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "iilfm/error.hpp"
#include "iilfm/sim/sim.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm::sim {
namespace {

std::string temp_path(const std::string& name) {
  return (iilfm::testing::process_scratch_dir() / name).string();
}

GroundTruth tag_wall_truth(const SensorModel& sensor = mid40()) {
  const SceneSetup setup = named_scene("tag-wall");
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  return ground_truth(setup.scene, sensor, o);
}

TEST(GroundTruth, CornersOfThePaperTagInCanonicalOrder) {
  const GroundTruth truth = tag_wall_truth();
  ASSERT_EQ(truth.markers.size(), 1u);
  const MarkerTruth& m = truth.markers[0];
  // Seen from the LiDAR (looking along +x), left is +y and up is +z.
  const std::array<Vec3, 4> expected = {Vec3(3.62, 0.086, 0.571), Vec3(3.62, -0.086, 0.571),
                                        Vec3(3.62, -0.086, 0.399), Vec3(3.62, 0.086, 0.399)};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR((m.corners_world[i] - expected[i]).norm(), 0, 1e-12) << "corner " << i;
    EXPECT_NEAR((m.corners_lidar[i] - (expected[i] - Vec3(1.62, 0, 0.485))).norm(), 0, 1e-12);
    EXPECT_NEAR((m.corners_world[(i + 1) % 4] - m.corners_world[i]).norm(), 0.172, 1e-12);
  }
  const Vec3& tl = m.corners_world[0];
  const Vec3& br = m.corners_world[2];
  EXPECT_GT(tl.y(), br.y());
  EXPECT_GT(tl.z(), br.z());
  EXPECT_TRUE(m.visible);
  EXPECT_NEAR((m.T_lidar_marker.translation() - Vec3(2, 0, 0)).norm(), 0, 1e-12);
  // The printed face (marker z) points back at the LiDAR.
  EXPECT_NEAR((m.T_lidar_marker.linear().col(2) - Vec3(-1, 0, 0)).norm(), 0, 1e-12);
}

TEST(GroundTruth, CornersFollowTheMarkerWhenTurnedInItsPlane) {
  // Turned 90 deg counter-clockwise as the viewer sees it, the top-left corner moves to the
  // bottom-left of the view.
  const MarkerSpec m = wall_marker("apriltag:tag36h11", 0, 0.2, 3, 0, 0, 90);
  const std::array<Vec3, 4> c = marker_corners_world(m);
  EXPECT_NEAR((c[0] - Vec3(3, 0.1, -0.1)).norm(), 0, 1e-12);
  EXPECT_NEAR((c[1] - Vec3(3, 0.1, 0.1)).norm(), 0, 1e-12);
}

TEST(GroundTruth, VisibilityNeedsFovRangeAndTheFrontFace) {
  SimOptions o;
  Scene scene = wall_scene({wall_marker("apriltag:tag36h11", 0, 0.2, 3, 0, 0),
                            wall_marker("apriltag:tag36h11", 1, 0.2, 3, 2.5, 0),
                            wall_marker("apriltag:tag36h11", 2, 0.2, 300, 0, 0)},
                           3, -1);
  MarkerSpec away = wall_marker("apriltag:tag36h11", 3, 0.2, 3, 0, 0.5);
  away.T_world_marker.linear() =
      Eigen::AngleAxisd(M_PI, Vec3::UnitZ()).toRotationMatrix() * away.T_world_marker.linear();
  scene.markers.push_back(away);
  const GroundTruth mid = ground_truth(scene, mid40(), o);
  EXPECT_TRUE(mid.markers[0].visible);
  EXPECT_FALSE(mid.markers[1].visible);  // 40 deg to the side: outside the 19.2 deg cone
  EXPECT_FALSE(mid.markers[2].visible);  // beyond 260 m
  EXPECT_FALSE(mid.markers[3].visible);  // printed face looks away
  const GroundTruth vlp = ground_truth(scene, vlp16(), o);
  EXPECT_TRUE(vlp.markers[1].visible);  // a spinning sensor sees all around
  EXPECT_FALSE(vlp.markers[2].visible);
}

// LiDARTag's ccw_10m ground truth vertices (in the LiDAR frame), as a set.
TEST(GroundTruth, Ccw10mSceneReproducesThePublishedVertices) {
  const SceneSetup setup = named_scene("ccw10m");
  EXPECT_EQ(setup.sensor, "ultrapuck");
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  const GroundTruth truth = ground_truth(setup.scene, ultra_puck(), o);
  ASSERT_EQ(truth.markers.size(), 1u);
  EXPECT_EQ(truth.markers[0].family, "apriltag:tag16h5");
  EXPECT_TRUE(truth.markers[0].visible);
  const std::array<Vec3, 4> published = {Vec3(9.74, 0.76, -0.16), Vec3(9.94, 0.07, -0.73),
                                         Vec3(10.27, -0.41, -0.03), Vec3(10.07, 0.27, 0.54)};
  for (const Vec3& p : published) {
    double nearest = 1e9;
    for (const Vec3& c : truth.markers[0].corners_lidar)
      nearest = std::min(nearest, (c - p).norm());
    EXPECT_LT(nearest, 0.05) << p.transpose();
  }
}

TEST(GroundTruth, JsonRoundTrip) {
  SceneSetup setup = named_scene("grid");
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  o.frames = 2;
  o.seed = 42;
  const SimResult r = simulate(setup.scene, mid40(), o);
  const std::string path = temp_path("truth.json");
  write_ground_truth_json(path, r.truth);

  std::ifstream in(path);
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.at("sensor"), "mid40");
  EXPECT_EQ(doc.at("T_world_lidar").size(), 4u);
  EXPECT_DOUBLE_EQ(doc.at("T_world_lidar")[0][3].get<double>(), 3.62 - 3.5);
  EXPECT_EQ(doc.at("markers").size(), 35u);
  EXPECT_EQ(doc.at("markers")[34].at("id"), 34);

  const GroundTruth back = read_ground_truth_json(path);
  EXPECT_EQ(back.seed, 42u);
  EXPECT_EQ(back.frames, 2);
  ASSERT_EQ(back.markers.size(), r.truth.markers.size());
  for (std::size_t i = 0; i < back.markers.size(); ++i) {
    const MarkerTruth &a = r.truth.markers[i], &b = back.markers[i];
    EXPECT_EQ(a.family, b.family);
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.visible, b.visible);
    EXPECT_EQ(a.points_on_marker, b.points_on_marker);
    EXPECT_TRUE(a.T_lidar_marker.isApprox(b.T_lidar_marker, 1e-12));
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR((a.corners_lidar[k] - b.corners_lidar[k]).norm(), 0, 1e-12);
  }
  std::remove(path.c_str());
  EXPECT_THROW(read_ground_truth_json(path), InputError);
}

TEST(GroundTruth, MarkerMapYamlParsesBackWithTheSameCorners) {
  const SceneSetup setup = named_scene("grid");
  const std::string path = temp_path("map.yaml");
  write_marker_map_yaml(path, setup.scene);
  const YAML::Node map = YAML::LoadFile(path);
  ASSERT_TRUE(map["markers"].IsSequence());
  ASSERT_EQ(map["markers"].size(), setup.scene.markers.size());
  for (std::size_t i = 0; i < setup.scene.markers.size(); ++i) {
    const YAML::Node m = map["markers"][i];
    EXPECT_EQ(m["family"].as<std::string>(), "apriltag:tag36h11");
    EXPECT_EQ(m["id"].as<int>(), static_cast<int>(i));
    const std::array<Vec3, 4> expected = marker_corners_world(setup.scene.markers[i]);
    ASSERT_EQ(m["corners"].size(), 4u);
    for (int k = 0; k < 4; ++k) {
      const Vec3 c(m["corners"][k][0].as<double>(), m["corners"][k][1].as<double>(),
                   m["corners"][k][2].as<double>());
      EXPECT_NEAR((c - expected[k]).norm(), 0, 1e-6) << "marker " << i << " corner " << k;
    }
  }
  std::remove(path.c_str());
}

TEST(GroundTruth, UnwritablePathsAreInputErrors) {
  const GroundTruth truth = tag_wall_truth();
  EXPECT_THROW(write_ground_truth_json("/nonexistent-dir/truth.json", truth), InputError);
  EXPECT_THROW(write_marker_map_yaml("/nonexistent-dir/map.yaml", Scene{}), InputError);
}

TEST(Scenes, UnknownSceneNamesListTheKnownOnes) {
  try {
    named_scene("atrium");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tag-wall, grid, ccw10m"), std::string::npos);
  }
  EXPECT_THROW(named_scene("tag-wall", SceneParams{{}, {}, {}, -1.0}), InputError);
}

TEST(Scenes, ParamsOverrideTheDefaults) {
  SceneParams p;
  p.family = "apriltag:tag25h9";
  p.id = 7;
  p.marker_size_m = 0.3;
  p.distance_m = 5;
  const SceneSetup setup = named_scene("tag-wall", p);
  ASSERT_EQ(setup.scene.markers.size(), 1u);
  EXPECT_EQ(setup.scene.markers[0].family, "apriltag:tag25h9");
  EXPECT_EQ(setup.scene.markers[0].id, 7);
  EXPECT_DOUBLE_EQ(setup.scene.markers[0].size_m, 0.3);
  EXPECT_NEAR(setup.T_world_lidar.translation().x(), 3.62 - 5, 1e-12);
}

// The paper's Fig. 1(a): 35 tag36h11 and 4 ArUco markers on one wall, every one inside the
// Mid-40's cone, no sheet overlapping another, and the families carried into the files.
TEST(Scenes, PaperGridHas35TagsAnd4ArucoMarkers) {
  const SceneSetup setup = named_scene("paper-grid");
  ASSERT_EQ(setup.scene.markers.size(), 39u);
  for (int i = 0; i < 35; ++i) {
    EXPECT_EQ(setup.scene.markers[i].family, "apriltag:tag36h11");
    EXPECT_EQ(setup.scene.markers[i].id, i);
    EXPECT_DOUBLE_EQ(setup.scene.markers[i].size_m, 0.172);
  }
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(setup.scene.markers[35 + i].family, "aruco:DICT_4X4_50");
    EXPECT_EQ(setup.scene.markers[35 + i].id, i);
    EXPECT_DOUBLE_EQ(setup.scene.markers[35 + i].size_m, 0.16);
  }
  // Printed sheets (black square plus the white margin) keep apart: 21.5 cm tag sheets, 21.3 cm
  // ArUco sheets (6 of 8 cells black).
  const auto half_sheet = [](const MarkerSpec& m) {
    return m.family == "aruco:DICT_4X4_50" ? m.size_m * 8 / 12 : m.size_m * 10 / 16;
  };
  for (std::size_t a = 0; a < 39; ++a) {
    for (std::size_t b = a + 1; b < 39; ++b) {
      const Vec3 d = setup.scene.markers[a].T_world_marker.translation() -
                     setup.scene.markers[b].T_world_marker.translation();
      const double reach = half_sheet(setup.scene.markers[a]) + half_sheet(setup.scene.markers[b]);
      EXPECT_TRUE(std::abs(d.y()) > reach || std::abs(d.z()) > reach) << a << " and " << b;
    }
  }
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  o.frames = 1;
  const SimResult r = simulate(setup.scene, mid40(), o);
  for (const MarkerTruth& m : r.truth.markers) EXPECT_TRUE(m.visible) << m.family << " " << m.id;

  const std::string truth_path = temp_path("paper_grid.json"), map_path = temp_path("pg.yaml");
  write_ground_truth_json(truth_path, r.truth);
  write_marker_map_yaml(map_path, setup.scene);
  std::ifstream in(truth_path);
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.at("markers")[38].at("family"), "aruco:DICT_4X4_50");
  EXPECT_EQ(doc.at("markers")[38].at("id"), 3);
  EXPECT_EQ(read_ground_truth_json(truth_path).markers[36].family, "aruco:DICT_4X4_50");
  const YAML::Node map = YAML::LoadFile(map_path);
  EXPECT_EQ(map["markers"][35]["family"].as<std::string>(), "aruco:DICT_4X4_50");
  EXPECT_EQ(map["markers"][34]["family"].as<std::string>(), "apriltag:tag36h11");
  std::remove(truth_path.c_str());
  std::remove(map_path.c_str());

  SceneParams family;
  family.family = "apriltag:tag25h9";
  EXPECT_THROW(named_scene("paper-grid", family), InputError);
  EXPECT_THROW(named_scene("paper-grid", SceneParams{{}, {}, {}, 0.0}), InputError);
}

TEST(Scenes, ArucoFamiliesPrintInNamedScenes) {
  SceneParams p;
  p.family = "aruco:DICT_ARUCO_ORIGINAL";
  p.marker_size_m = 0.4;
  const SceneSetup setup = named_scene("grid", p);
  ASSERT_EQ(setup.scene.markers.size(), 35u);
  EXPECT_EQ(setup.scene.markers[34].family, "aruco:DICT_ARUCO_ORIGINAL");
  p.family = "aruco:DICT_4X4_50";
  p.id = 20;  // the grid would need ids up to 54
  EXPECT_THROW(named_scene("grid", p), InputError);
}

}  // namespace
}  // namespace iilfm::sim
