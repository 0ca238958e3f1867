// ArUco markers in simulated scans, end to end: a noise-free scan lands the corners within one
// pixel's footprint, and the paper's grid of 35 tag36h11 and 4 ArUco markers is found complete with
// both families enabled in one run (library and `iilfm` program).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_run.hpp"
#include "iilfm/eval/case.hpp"
#include "iilfm/sensor.hpp"
#include "support/scratch_dir.hpp"

namespace iilfm::testing {
namespace {

namespace fs = std::filesystem;

constexpr double kDeg = M_PI / 180.0;

// One Mid-40 pixel (0.05 deg) at `distance` metres.
double mid40_pixel_footprint(double distance) { return distance * std::tan(0.05 * kDeg); }

eval::CaseSpec noise_free_tag_wall(const std::string& family, int id, double size) {
  eval::CaseSpec spec;
  spec.scene_params.family = family;
  spec.scene_params.id = id;
  spec.scene_params.marker_size_m = size;
  spec.physics.range_sigma_m = 0;
  spec.physics.intensity_sigma = 0;
  return spec;
}

void print_score(const char* what, const eval::CaseScore& s) {
  std::printf(
      "[ measured ] %s: found %d/%d, corner mean %.2f mm, max %.2f mm, LiDAR %.2f mm %.3f deg\n",
      what, s.detected, s.visible, s.corner_error_mean * 1000, s.corner_error_max * 1000,
      s.position_error * 1000, s.rotation_error_deg);
}

// The paper's 16 cm 4x4 marker, 2 m ahead, 40 Mid-40 frames without noise.
TEST(SimAruco, NoiseFreeMid40CornersWithinOnePixelFootprint) {
  const eval::SimulatedCase c =
      eval::simulate_case(noise_free_tag_wall("aruco:DICT_4X4_50", 5, 0.16), 1);
  ASSERT_EQ(c.scan.truth.markers.at(0).family, "aruco:DICT_4X4_50");
  const eval::CaseScore s = eval::run_case(c, LiftMethod::kPlane);
  print_score("noise-free Mid-40, 16 cm DICT_4X4_50 at 2 m", s);
  ASSERT_EQ(s.detected, 1);
  EXPECT_EQ(s.false_positives + s.wrong_ids, 0);
  EXPECT_EQ(s.corners, 4);
  EXPECT_LT(s.corner_error_max, mid40_pixel_footprint(2.0));
}

// Turned 120 deg in its plane on a wall yawed 20 deg: a wrong corner order would put every corner
// a marker side away.
TEST(SimAruco, TurnedOriginalArucoOnAYawedWallKeepsItsCornerOrder) {
  const double distance = 2.5, size = 0.3;
  sim::Scene scene;
  sim::Wall wall = sim::upright_wall(Vec3(distance, 0, 0), 180 - 20, 4, 3);
  scene.walls = {wall};
  scene.markers = {sim::marker_on_wall(wall, "aruco:DICT_ARUCO_ORIGINAL", 321, size, 0, 0, 120)};
  sim::SimOptions options;
  options.range_sigma_m = 0;
  options.intensity_sigma = 0;
  options.frames = 40;
  const sim::SimResult r = sim::simulate(scene, sim::mid40(), options);
  PipelineOptions po;
  apply_sensor_preset(find_sensor_preset("mid40"), po);
  po.families = {"aruco:DICT_ARUCO_ORIGINAL"};
  po.map = eval::map_of(scene);
  Pipeline pipeline(po);
  const eval::CaseScore s = eval::score_frame(pipeline.process(r.cloud), r.truth);
  print_score("noise-free Mid-40, 30 cm DICT_ARUCO_ORIGINAL turned 120 deg at 2.5 m", s);
  ASSERT_EQ(s.detected, 1);
  EXPECT_EQ(s.false_positives + s.wrong_ids, 0);
  // The wall is yawed, so a pixel reaches a little further than straight ahead.
  EXPECT_LT(s.corner_error_max, mid40_pixel_footprint(distance) / std::cos(20 * kDeg));
}

// The paper's Fig. 1(a) / 8(a): 35 tag36h11 and 4 DICT_4X4_50 on one wall, both families in one
// run, with the realistic 2 cm range noise.
TEST(SimAruco, PaperGridFindsAll39MarkersWithBothFamilies) {
  for (std::uint64_t seed : {1, 2, 3}) {
    eval::CaseSpec spec;
    spec.scene = "paper-grid";
    const eval::SimulatedCase c = eval::simulate_case(spec, seed);
    const PipelineOptions options = eval::pipeline_options_for(c, LiftMethod::kPlane);
    EXPECT_EQ(options.families,
              (std::vector<std::string>{"apriltag:tag36h11", "aruco:DICT_4X4_50"}));
    Pipeline pipeline(options);
    const FrameResult& r = pipeline.process(c.scan.cloud);
    const eval::CaseScore s = eval::score_frame(r, c.scan.truth);
    print_score(("paper-grid seed " + std::to_string(seed)).c_str(), s);
    EXPECT_EQ(s.visible, 39);
    EXPECT_EQ(s.detected, 39) << "seed " << seed;
    EXPECT_EQ(s.false_positives, 0);
    EXPECT_EQ(s.wrong_ids, 0);
    EXPECT_LT(s.corner_error_max, 0.01);
    int aruco = 0;
    for (const MarkerResult& m : r.markers) aruco += m.detection.family == "aruco:DICT_4X4_50";
    EXPECT_EQ(aruco, 4);
    ASSERT_TRUE(r.pose);
    EXPECT_EQ(r.pose->markers_used.size(), 39u);
    EXPECT_LT(s.position_error, 0.005);
  }
}

TEST(SimAruco, CliDetectsThePaperGridWithTwoMarkerFamilies) {
  const fs::path d = iilfm::testing::process_scratch_dir() / "aruco";
  fs::create_directories(d);
  const std::string pcd = (d / "grid.pcd").string(), map = (d / "grid.yaml").string(),
                    truth = (d / "truth.json").string(), json = (d / "out.json").string();
  ASSERT_EQ(run_cli("sim --scene paper-grid --seed 7 --out " + pcd + " --map " + map + " --truth " +
                    truth)
                .status,
            0);
  ASSERT_EQ(run_cli("detect " + pcd + " --sensor mid40 --marker apriltag:tag36h11 --marker " +
                    "aruco:DICT_4X4_50 --map " + map + " --json " + json)
                .status,
            0);
  const nlohmann::json t = nlohmann::json::parse(slurp(truth));
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  using Key = std::pair<std::string, int>;
  const auto key = [](const nlohmann::json& m) {
    return Key(m["family"].get<std::string>(), m["id"].get<int>());
  };
  std::set<Key> expected, found;
  for (const auto& m : t["markers"]) expected.insert(key(m));
  for (const auto& m : j["markers"]) {
    found.insert(key(m));
    EXPECT_TRUE(m["in_map"].get<bool>()) << m["family"] << " " << m["id"];
  }
  ASSERT_EQ(expected.size(), 39u);
  EXPECT_EQ(expected.count(Key("aruco:DICT_4X4_50", 3)), 1u);
  EXPECT_EQ(j["markers"].size(), 39u);  // nothing twice, nothing else
  EXPECT_EQ(found, expected);
  ASSERT_FALSE(j["pose"].is_null());
  EXPECT_EQ(j["pose"]["markers_used"].size(), 39u);
  fs::remove_all(d);
}

}  // namespace
}  // namespace iilfm::testing
