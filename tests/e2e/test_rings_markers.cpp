// Concentric-ring markers (rings:ring7h3, rings:ring9h3) on simulated scans: the scene (b),
// three ring markers on a wall found with their ids, their centres lifted, and one LiDAR pose from
// the three centres; and no ring marker anywhere in marker-free scenes, simulated or real.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "iilfm/eval/case.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/sim/scenes.hpp"
#include "real_data.hpp"

namespace iilfm::testing {
namespace {

struct RingsScan {
  sim::SimResult scan;
  FrameResult result;
};

// Three 30 cm ring markers (ids 3, 11, 14, 0.4-0.75 m apart) on a wall `distance_m` ahead of a
// Mid-40 and yawed `wall_yaw_deg`, 40 frames with the simulator's default noise, the map holding
// all three.
RingsScan three_markers_on_a_wall(const std::string& family, std::uint64_t seed, double distance_m,
                                  double wall_yaw_deg) {
  sim::Scene scene;
  const sim::Wall wall = sim::upright_wall(Vec3(distance_m, 0, 0.5), 180 - wall_yaw_deg, 4, 2.5);
  scene.walls = {wall};
  const int ids[] = {3, 11, 14};
  const double u[] = {-0.4, 0.0, 0.35}, v[] = {0.15, -0.15, 0.1};
  for (int k = 0; k < 3; ++k)
    scene.markers.push_back(sim::marker_on_wall(wall, family, ids[k], 0.3, u[k], v[k]));
  sim::SimOptions options;
  options.T_world_lidar.translation() = Vec3(0, 0.1, 0.45);
  options.frames = 40;
  options.seed = seed;
  RingsScan out{sim::simulate(scene, sim::sensor_model("mid40"), options), {}};
  PipelineOptions po;
  apply_sensor_preset(find_sensor_preset("mid40"), po);
  po.families = {family};
  po.map = eval::map_of(scene);
  po.pose.min_corners = 3;  // one keypoint per marker: three markers make a pose
  Pipeline pipeline(po);
  out.result = pipeline.process(out.scan.cloud);
  return out;
}

// The lifted centre of each detected marker against the true one, metres (largest).
double worst_centre_error(const RingsScan& s, int* matched) {
  double worst = 0;
  *matched = 0;
  for (const MarkerResult& m : s.result.markers) {
    for (const sim::MarkerTruth& t : s.scan.truth.markers) {
      if (t.id != m.detection.id || t.family != m.detection.family) continue;
      EXPECT_EQ(m.corners.size(), 1u);
      if (m.corners.empty() || !m.corners[0].valid()) continue;
      worst = std::max(worst, (m.corners[0].point - t.T_lidar_marker.translation()).norm());
      ++*matched;
    }
  }
  return worst;
}

// The scene (b). Measured (worst of the three centres; LiDAR pose from the three): wall
// yawed 15 deg, 0.29-0.49 mm, 0.9-2.0 mm and 0.02-0.04 deg; yawed 45 deg, 0.24-0.57 mm, 1.0-2.7 mm
// and 0.03-0.06 deg, over 2.2-3 m and both families. The 45 deg wall needs the rings sampled with
// the perspective shift of their centres (docs/detectors.md); at 55 deg some markers are lost.
TEST(SimRings, ThreeRingMarkersOnAWallAreFoundAndGiveOnePose) {
#ifdef NDEBUG
  const std::vector<double> kDistances = {2.2, 2.6, 3.0};
#else
  const std::vector<double> kDistances = {2.6};  // sanitizer builds simulate 20-40x slower
#endif
  for (const std::string family : {"rings:ring9h3", "rings:ring7h3"}) {
    for (const double yaw : {15.0, 45.0}) {
      for (const double distance : kDistances) {
        const auto seed = static_cast<std::uint64_t>(distance * 10 + yaw);
        const RingsScan s = three_markers_on_a_wall(family, seed, distance, yaw);
        const eval::CaseScore score = eval::score_frame(s.result, s.scan.truth);
        int matched = 0;
        const double centre_error = worst_centre_error(s, &matched);
        char what_text[96];
        std::snprintf(what_text, sizeof what_text, "%s at %.1f m, wall yawed %.0f deg",
                      family.c_str(), distance, yaw);
        const std::string what = what_text;
        std::printf(
            "[ measured ] Mid-40, three 30 cm %s: found %d/3, worst centre %.2f mm, LiDAR "
            "%.2f mm %.3f deg; one marker's own pose: face %.3f deg (claimed %.3f), NEES %.1f\n",
            what.c_str(), score.detected, centre_error * 1000,
            score.pose ? score.position_error * 1000 : -1.0,
            score.pose ? score.rotation_error_deg : -1.0, score.marker_rotation_error_mean_deg,
            score.marker_rotation_sigma_mean_deg, score.marker_nees_mean);
        EXPECT_EQ(score.detected, 3) << what;
        EXPECT_EQ(score.false_positives + score.wrong_ids, 0) << what;
        EXPECT_EQ(matched, 3) << what;
        EXPECT_LT(centre_error, 0.0015) << what;
        // Each marker alone: its centre and the fitted plane's normal, the turn about the normal
        // a convention (measured face error 0.08-0.18 deg).
        EXPECT_EQ(score.marker_poses, 3) << what;
        EXPECT_LT(score.marker_rotation_error_mean_deg, 0.4) << what;
        for (const MarkerResult& m : s.result.markers) EXPECT_FALSE(m.turn_known) << what;
        ASSERT_TRUE(s.result.pose) << what << ": " << s.result.pose_missing_reason;
        EXPECT_EQ(s.result.pose->markers_used.size(), 3u) << what;
        EXPECT_LT(score.position_error, 0.006) << what;
        EXPECT_LT(score.rotation_error_deg, 0.2) << what;
      }
    }
  }
}

// The simulator's scenes with their markers taken away, 50 seeds: a room (Avia) and a wall with
// a floor at 1.5-4 m (Mid-40). Neither ring family reports anything.
TEST(SimRings, MarkerFreeScenesGiveNoRingMarker) {
#ifdef NDEBUG
  constexpr std::uint64_t kSeeds = 50;
#else
  constexpr std::uint64_t kSeeds = 6;            // sanitizer builds simulate 20-40x slower
#endif
  int frames_seen = 0;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    sim::SceneSetup setup;
    if (seed % 2 == 0) {
      setup = sim::named_scene("room");
      setup.scene.markers.clear();
    } else {
      setup.scene = sim::wall_scene({}, 1.5 + 0.05 * static_cast<double>(seed));
      setup.T_world_lidar.translation() = Vec3(0, 0, 0.5);
      setup.sensor = "mid40";
    }
    sim::SimOptions options;
    options.T_world_lidar = setup.T_world_lidar;
    options.frames = 10;
    options.seed = seed;
    const sim::SimResult r = sim::simulate(setup.scene, sim::sensor_model(setup.sensor), options);
    PipelineOptions po;
    apply_sensor_preset(find_sensor_preset(setup.sensor), po);
    po.families = {"rings:ring7h3", "rings:ring9h3"};
    Pipeline pipeline(po);
    const FrameResult& result = pipeline.process(r.cloud);
    EXPECT_EQ(result.markers.size(), 0u) << "seed " << seed << " (" << setup.sensor << ")";
    frames_seen += result.image.geometry.width > 0;
  }
  EXPECT_EQ(frames_seen, static_cast<int>(kSeeds));
}

// The same scene through the CLI: a scene file with three rings:ring9h3 markers, `iilfm sim`,
// then `iilfm detect` with the simulator's map: three ids, their centres in the JSON, a pose, and
// the image overlay and HTML report written.
TEST(SimRings, CliSimulatesAndDetectsRingMarkersFromASceneFile) {
  const auto dir = cli_temp_dir();
  const std::string scene = (dir / "rings.yaml").string(), pcd = (dir / "rings.pcd").string(),
                    map = (dir / "rings_map.yaml").string(), json = (dir / "rings.json").string(),
                    png = (dir / "rings.png").string(), html = (dir / "rings.html").string();
  std::ofstream(scene)
      << "lidar: {sensor: mid40, position: [0, 0.1, 0.45], rpy_deg: [0, 0, 0]}\n"
         "walls:\n"
         "  - {centre: [2.5, 0, 0.5], rpy_deg: [90, 0, -75], width: 4, height: 2.5}\n"
         "markers:\n"
         "  - {family: rings:ring9h3, id: 3, size: 0.3, on_wall: 0, at: [-0.4, 0.15]}\n"
         "  - {family: rings:ring9h3, id: 11, size: 0.3, on_wall: 0, at: [0, -0.15]}\n"
         "  - {family: rings:ring9h3, id: 14, size: 0.3, on_wall: 0, at: [0.35, 0.1]}\n";
  const CliRun sim =
      run_cli("sim --scene-file " + scene + " --frames 40 --seed 3 --out " + pcd + " --map " + map);
  ASSERT_EQ(sim.status, 0) << sim.err;
  const CliRun detect =
      run_cli("detect " + pcd + " --sensor mid40 --marker rings:ring9h3 --map " + map +
              " --min-pose-corners 3 --json " + json + " --image " + png + " --html " + html);
  ASSERT_EQ(detect.status, 0) << detect.err;
  // The overlay and the report draw one keypoint and the outline of each marker.
  EXPECT_GT(std::filesystem::file_size(png), 1000u);
  EXPECT_GT(std::filesystem::file_size(html), 1000u);
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j["markers"].size(), 3u);
  std::vector<int> ids;
  for (const auto& m : j["markers"]) {
    EXPECT_EQ(m["family"], "rings:ring9h3");
    EXPECT_EQ(m["corners_px"].size(), 1u);
    EXPECT_TRUE(m["in_map"].get<bool>());
    ids.push_back(m["id"].get<int>());
  }
  EXPECT_EQ(ids, (std::vector<int>{3, 11, 14}));
  ASSERT_FALSE(j["pose"].is_null()) << j.dump();
  const auto& T = j["pose"]["T_world_lidar"];
  EXPECT_NEAR(T[0][3].get<double>(), 0.0, 0.005);
  EXPECT_NEAR(T[1][3].get<double>(), 0.1, 0.005);
  EXPECT_NEAR(T[2][3].get<double>(), 0.45, 0.005);
}

// The real Pandar64 scans (../shared/data/real, SOURCES.md) show calibration boards with a
// checkerboard and high-contrast circles, and no ring marker: both families stay silent, on the
// binarised and on the gray image.
TEST(RealRings, Pandar64ScansReportNoRingMarker) {
  const auto scans = pandar64_scans();
  if (scans.empty()) GTEST_SKIP() << "no real data at " << real_data_dir();
  for (const bool binarize : {true, false}) {
    PipelineOptions po;
    apply_sensor_preset(find_sensor_preset("pandar64"), po);
    po.preprocess.binarize = binarize;
    po.families = {"rings:ring7h3", "rings:ring9h3"};
    Pipeline pipeline(po);
    for (const auto& scan : scans) {
      const FrameResult& r = pipeline.process(io::read_cloud(scan.string()).cloud);
      EXPECT_EQ(r.markers.size(), 0u) << scan << (binarize ? " binarised" : " gray");
    }
  }
}

}  // namespace
}  // namespace iilfm::testing
