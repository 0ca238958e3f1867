// PipelineOptions::max_square_error: a detector's chance match on speckle lifts to no square and
// is dropped; printed markers lift to squares and stay.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
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
}

}  // namespace
}  // namespace iilfm
