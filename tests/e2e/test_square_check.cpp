// The nearest square to a marker's lifted corners. PipelineOptions::max_square_error: a
// detector's chance match on speckle lifts to no square and is dropped; printed markers lift to
// squares and stay. MarkerResult::size_disagrees: the square's edge against the size given.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "iilfm/eval/case.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/sim/physics_request.hpp"
#include "iilfm/sim/scene_file.hpp"
#include "iilfm/sim/scenes.hpp"
#include "iilfm/sim/sensor_models.hpp"
#include "iilfm/sim/simulate.hpp"

namespace iilfm {
namespace {

using testing::cli_temp_dir;
using testing::CliRun;
using testing::run_cli;
using testing::slurp;

// The room scene (data/scenes/room.yaml) seen by a Mid-70 from (-1.5, -1, 1.0) m, 40 frames,
// as `iilfm sim --scene-file room.yaml --sensor mid70 --lidar-xyz -1.5 -1 1.0 --seed 2` makes it.
sim::SimResult mid70_room(bool with_markers) {
  sim::SceneSetup setup = sim::named_scene("room");
  if (!with_markers) setup.scene.markers.clear();
  const sim::SensorModel sensor = sim::sensor_model("mid70");
  sim::SimOptions options;
  options.T_world_lidar = setup.T_world_lidar;
  options.T_world_lidar.translation() = Vec3(-1.5, -1, 1.0);
  options.frames = sim::default_frames(sensor);
  options.seed = 2;
  sim::apply_physics(sim::PhysicsRequest{}, options);
  return sim::simulate(setup.scene, sensor, options);
}

PipelineOptions mid70_options(double max_square_error) {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("mid70"), options);
  options.families = {"apriltag:tag16h5"};
  options.max_square_error = max_square_error;
  return options;
}

// Without markers the crate's side returns 40, the preset's threshold, so its binary image is
// speckle; tag16h5 (30 codes of 16 bits, no bit corrected here) reads id 13 in one quad of it.
// Its lifted corners are 6.7 to 15 cm apart, 0.23 of its 10 cm edge from the nearest square.
// The preset then retries the frame with the local threshold (found nothing at its own).
TEST(SquareCheck, DropsTheChanceMatchAMarkerFreeRoomGivesTag16h5) {
  const sim::SimResult room = mid70_room(false);
  Pipeline unchecked(mid70_options(0));
  const FrameResult& seen = unchecked.process(room.cloud);
  ASSERT_EQ(seen.markers.size(), 1u);  // the chance match is there without the check
  EXPECT_EQ(seen.markers[0].detection.id, 13);
  EXPECT_EQ(seen.not_square_dropped, 0u);
  EXPECT_FALSE(seen.threshold_retry);  // a marker was found: nothing to retry

  Pipeline checked(mid70_options(PipelineOptions{}.max_square_error));
  const FrameResult& r = checked.process(room.cloud);
  EXPECT_TRUE(r.markers.empty());
  EXPECT_EQ(r.not_square_dropped, 1u);
  // A dropped chance match is no marker: the Livox preset's local retry runs, and finds nothing.
  ASSERT_TRUE(r.threshold_retry);
  EXPECT_TRUE(r.threshold_retry->local);
  EXPECT_EQ(r.threshold_retry->found, 0u);
}

// The same room with its four 30 cm tag36h11 markers: all found, none dropped.
TEST(SquareCheck, KeepsEveryPrintedMarker) {
  const sim::SimResult room = mid70_room(true);
  PipelineOptions options = mid70_options(PipelineOptions{}.max_square_error);
  options.families = {"apriltag:tag36h11"};
  Pipeline pipeline(options);
  const FrameResult& r = pipeline.process(room.cloud);
  EXPECT_EQ(r.not_square_dropped, 0u);
  int visible = 0;
  for (const sim::MarkerTruth& m : room.truth.markers) visible += m.visible;
  EXPECT_GE(visible, 3);
  EXPECT_EQ(static_cast<int>(r.markers.size()), visible);
}

// The same scan through `iilfm sim` and `iilfm detect`: the JSON counts the dropped detection and
// the report says why.
TEST(SquareCheck, TheCliCountsWhatItDropped) {
  const auto dir = cli_temp_dir();
  const std::string scene = (dir / "empty_room.yaml").string(),
                    pcd = (dir / "empty_room.pcd").string(),
                    json = (dir / "empty_room.json").string();
  sim::SceneSetup room = sim::named_scene("room");
  room.scene.markers.clear();
  sim::write_scene_yaml(scene, room);
  ASSERT_EQ(run_cli("sim --scene-file " + scene +
                    " --sensor mid70 --lidar-xyz -1.5 -1 1.0 --seed 2 --out " + pcd)
                .status,
            0);
  const CliRun r =
      run_cli("detect " + pcd + " --sensor mid70 --marker apriltag:tag16h5 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_TRUE(j["markers"].empty());
  EXPECT_EQ(j.value("detections_not_square", 0), 1);
  EXPECT_NE(r.out.find("0 marker(s); 1 detection(s) dropped: their lifted corners are no square"),
            std::string::npos)
      << r.out;

  // --no-square-check keeps it.
  const CliRun kept =
      run_cli("detect " + pcd +
              " --sensor mid70 --marker apriltag:tag16h5 --no-square-check --json " + json);
  ASSERT_EQ(kept.status, 0) << kept.err;
  const nlohmann::json k = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(k["markers"].size(), 1u);
  EXPECT_EQ(k["markers"][0]["id"], 13);
  EXPECT_GT(k["markers"][0]["square_rms_m"].get<double>(),
            0.15 * k["markers"][0]["measured_size_m"].get<double>());
  EXPECT_FALSE(k.contains("detections_not_square"));
}

// A 17.2 cm tag 2 m from a Mid-40 (40 frames) and a 40 cm one 10 m from an ULTRA Puck: the
// measured size is the black square's edge within its allowance, and a size a quarter too large
// (the whole tag36h11 with its white margin: 10 cells, not 8) disagrees where the scan can tell.
TEST(SizeCheck, TheMeasuredSizeIsTheBlackSquaresEdge) {
  struct Case {
    const char* sensor;
    double distance_m, size_m, most_error_m;
    bool margin_told;  // whether a quarter too large is beyond the scan's allowance
  };
  // Measured (seed 1): Mid-40 0.3 mm, ULTRA Puck 12 mm under (allowance 156 mm: its rings are
  // 58 mm apart there).
  for (const Case& k :
       {Case{"mid40", 2, 0.172, 0.002, true}, Case{"ultrapuck", 10, 0.4, 0.02, false}}) {
    SCOPED_TRACE(k.sensor);
    const eval::SimulatedCase c =
        eval::simulate_case(eval::tag_wall_spec(k.sensor, k.distance_m, k.size_m), 1);
    for (const double given : {k.size_m, 1.25 * k.size_m}) {
      PipelineOptions options = eval::pipeline_options_for(c, LiftMethod::kPlane);
      options.map.reset();
      options.marker_size = given;
      Pipeline pipeline(options);
      const FrameResult& r = pipeline.process(c.scan.cloud);
      ASSERT_EQ(r.markers.size(), 1u);
      const MarkerResult& m = r.markers[0];
      ASSERT_TRUE(m.lifted_square);
      EXPECT_NEAR(m.lifted_square->side_m, k.size_m, k.most_error_m);
      EXPECT_EQ(m.size_disagrees, given != k.size_m && k.margin_told) << "given " << given;
    }
  }
}

// The CLI notes a disagreeing size under the marker, and the JSON flags it.
TEST(SizeCheck, TheCliSaysWhenTheSizeGivenIsNotTheMeasuredOne) {
  const std::string sample = std::string(IILFM_SOURCE_DIR) + "/data/sample/mid40_tag_wall.pcd";
  const std::string json = (cli_temp_dir() / "size.json").string();
  CliRun r = run_cli("detect " + sample + " --sensor mid40 --marker-size 0.172 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j["markers"].size(), 1u);
  EXPECT_NEAR(j["markers"][0]["measured_size_m"].get<double>(), 0.172, 0.002);
  EXPECT_LT(j["markers"][0]["square_rms_m"].get<double>(), 0.002);
  EXPECT_FALSE(j["markers"][0].contains("size_disagrees"));
  EXPECT_EQ(r.out.find("note: it measures"), std::string::npos) << r.out;

  r = run_cli("detect " + sample + " --sensor mid40 --marker-size 0.215 --json " + json);
  ASSERT_EQ(r.status, 0) << r.err;
  j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["markers"][0].value("size_disagrees", false), true);
  EXPECT_NE(r.out.find("note: it measures 0.17"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("not the 0.215 m given"), std::string::npos) << r.out;

  // A sequence (a folder of two such scans) counts the results in its closing summary.
  const std::filesystem::path folder = cli_temp_dir() / "size_frames";
  std::filesystem::create_directories(folder);
  for (const char* name : {"000000.pcd", "000001.pcd"})
    std::filesystem::copy_file(sample, folder / name,
                               std::filesystem::copy_options::overwrite_existing);
  r = run_cli("detect " + folder.string() + " --sensor mid40 --marker-size 0.215 --jsonl " +
              (cli_temp_dir() / "size.jsonl").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("note: in 2 result(s) a marker (first apriltag:tag36h11/0) measured another "
                       "size"),
            std::string::npos)
      << r.out;
}

}  // namespace
}  // namespace iilfm
