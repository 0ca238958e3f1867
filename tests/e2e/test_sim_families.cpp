// Families beyond the square tag on simulated scans: AprilTag's circle families lifted and posed
// through their data-grid corners, one report when two back-ends decode the same tag, and a
// ChArUco board posed from all its corners.
#include <gtest/gtest.h>

#include "iilfm/eval/case.hpp"
#include "iilfm/sensor.hpp"

namespace iilfm::testing {
namespace {

void print_score(const std::string& what, const eval::CaseScore& s) {
  std::printf(
      "[ measured ] %s: found %d/%d, corner mean %.2f mm, max %.2f mm, marker %.2f mm %.3f deg, "
      "LiDAR %.2f mm %.3f deg\n",
      what.c_str(), s.detected, s.visible, s.corner_error_mean * 1000, s.corner_error_max * 1000,
      s.marker_position_error_mean * 1000, s.marker_rotation_error_mean_deg,
      s.position_error * 1000, s.rotation_error_deg);
}

// The paper's set-up (a Mid-40 2 m from the wall, 40 frames, the simulator's default noise) with a
// circle tag whose reported square (5 cells, the data grid's outer edge) is 17.2 cm.
TEST(SimFamilies, CircleTagsOnAMid40ScanAreFoundAndPosed) {
  for (const std::string family : {"apriltag:tagCircle21h7", "apriltag:tagCircle49h12"}) {
    eval::CaseSpec spec;
    spec.scene_params.family = family;
    spec.scene_params.id = 11;
    const eval::SimulatedCase c = eval::simulate_case(spec, 3);
    const eval::CaseScore s = eval::run_case(c, LiftMethod::kPlane);
    print_score("Mid-40 2 m, 17.2 cm " + family, s);
    ASSERT_EQ(s.detected, 1) << family;
    EXPECT_EQ(s.false_positives + s.wrong_ids, 0) << family;
    EXPECT_EQ(s.corners, 4);
    EXPECT_LT(s.corner_error_max, 0.006) << family;
    ASSERT_TRUE(s.pose) << family;
    EXPECT_LT(s.position_error, 0.01) << family;
    EXPECT_LT(s.rotation_error_deg, 1.0) << family;
  }
}

// The scene (b): three circle markers on a wall, one LiDAR pose from all of them.
TEST(SimFamilies, ThreeCircleMarkersOnAWallGiveOnePose) {
  sim::Scene scene;
  const sim::Wall wall = sim::upright_wall(Vec3(3, 0, 0.5), 180, 4, 2.5);
  scene.walls = {wall};
  for (int k = 0; k < 3; ++k)
    scene.markers.push_back(sim::marker_on_wall(wall, "apriltag:tagCircle21h7", 20 + k, 0.15,
                                                -0.6 + 0.6 * k, 0.2 * (k % 2), 30.0 * k));
  sim::SimOptions options;
  options.T_world_lidar.translation() = Vec3(0, 0.1, 0.45);
  options.frames = 40;
  options.seed = 7;
  const sim::SimResult r = sim::simulate(scene, sim::sensor_model("mid40"), options);
  PipelineOptions po;
  apply_sensor_preset(find_sensor_preset("mid40"), po);
  po.families = {"apriltag:tagCircle21h7"};
  po.map = eval::map_of(scene);
  Pipeline pipeline(po);
  const FrameResult& result = pipeline.process(r.cloud);
  const eval::CaseScore s = eval::score_frame(result, r.truth);
  print_score("Mid-40 3 m, three 15 cm tagCircle21h7", s);
  EXPECT_EQ(s.detected, 3);
  EXPECT_EQ(s.false_positives + s.wrong_ids, 0);
  ASSERT_TRUE(result.pose) << result.pose_missing_reason;
  EXPECT_EQ(result.pose->markers_used.size(), 3u);
  EXPECT_LT(s.position_error, 0.01);
  EXPECT_LT(s.rotation_error_deg, 0.5);
}

struct TwoBackEnds {
  eval::SimulatedCase c;
  PipelineOptions options;
};

// A tag printed as `printed`, scanned by a Mid-40 2 m away, with both back-ends that decode it.
TwoBackEnds tag_seen_by_two_back_ends(const std::string& printed,
                                      std::vector<std::string> families) {
  eval::CaseSpec spec;
  spec.scene_params.family = printed;
  spec.scene_params.id = 3;
  TwoBackEnds t{eval::simulate_case(spec, 2), {}};
  t.options = eval::pipeline_options_for(t.c, LiftMethod::kPlane);
  t.options.families = std::move(families);
  return t;
}

TEST(SimFamilies, TwoBackEndsDecodingOneTagGiveOneReport) {
  const std::vector<std::string> both = {"apriltag:tag36h11", "aruco:DICT_APRILTAG_36h11"};
  TwoBackEnds t = tag_seen_by_two_back_ends("apriltag:tag36h11", both);
  Pipeline pipeline(t.options);
  const FrameResult& r = pipeline.process(t.c.scan.cloud);
  // Both back-ends do decode it on the very image the pipeline used...
  std::vector<Detection> raw;
  for (const std::string& family : both) make_detector(family)->detect(r.preprocessed.detect, raw);
  ASSERT_EQ(raw.size(), 2u);
  EXPECT_EQ(raw[0].id, 3);
  EXPECT_EQ(raw[1].id, 3);
  // ...and the result holds one: the family listed first, which the map also knows.
  ASSERT_EQ(r.markers.size(), 1u);
  EXPECT_EQ(r.markers[0].detection.family, "apriltag:tag36h11");
  const eval::CaseScore s = eval::score_frame(r, t.c.scan.truth);
  EXPECT_EQ(s.false_positives + s.wrong_ids, 0);
  ASSERT_TRUE(s.pose);
  EXPECT_LT(s.position_error, 0.01);

  // Without a map the order decides: ArUco first keeps ArUco's decoding.
  t.options.families = {both[1], both[0]};
  t.options.map.reset();
  Pipeline reversed(t.options);
  const FrameResult& r2 = reversed.process(t.c.scan.cloud);
  ASSERT_EQ(r2.markers.size(), 1u);
  EXPECT_EQ(r2.markers[0].detection.family, "aruco:DICT_APRILTAG_36h11");
}

// A drawMarker print mapped as ArUco: the map's family wins over the family listed first, so
// the pose uses corners in the order the map describes.
TEST(SimFamilies, TheDecodingInTheMapWinsOverListOrder) {
  TwoBackEnds t = tag_seen_by_two_back_ends("aruco:DICT_APRILTAG_36h11",
                                            {"apriltag:tag36h11", "aruco:DICT_APRILTAG_36h11"});
  Pipeline pipeline(t.options);
  const FrameResult& r = pipeline.process(t.c.scan.cloud);
  ASSERT_EQ(r.markers.size(), 1u);
  EXPECT_EQ(r.markers[0].detection.family, "aruco:DICT_APRILTAG_36h11");
  EXPECT_TRUE(r.markers[0].in_map);
  const eval::CaseScore s = eval::score_frame(r, t.c.scan.truth);
  print_score("Mid-40 2 m, drawMarker DICT_APRILTAG_36h11 with both back-ends", s);
  ASSERT_TRUE(s.pose);
  EXPECT_LT(s.position_error, 0.01);
  EXPECT_LT(s.corner_error_max, 0.006);
}

// The scene (d): a ChArUco board (5 x 5 squares of 8 cm, DICT_4X4_50) on a wall 2.5 m from
// a Mid-40, 40 frames with the simulator's default noise. The board is one marker with 16
// keypoints; its map entry is its pose and square size.
TEST(SimFamilies, CharucoBoardIsOneMarkerPosedFromAllItsCorners) {
  const std::string family = "charuco:DICT_4X4_50:5x5";
  const double square = 0.08;
  sim::Scene scene;
  const sim::Wall wall = sim::upright_wall(Vec3(2.5, 0, 0.5), 180 - 15, 4, 2.5);
  scene.walls = {wall};
  scene.markers = {sim::marker_on_wall(wall, family, 0, square, 0.1, 0.05, 10)};
  sim::SimOptions options;
  options.T_world_lidar.translation() = Vec3(0, 0, 0.45);
  options.frames = 40;
  options.seed = 4;
  const sim::SimResult r = sim::simulate(scene, sim::sensor_model("mid40"), options);
  PipelineOptions po;
  apply_sensor_preset(find_sensor_preset("mid40"), po);
  po.families = {family};
  po.map = eval::map_of(scene);
  Pipeline pipeline(po);
  const FrameResult& result = pipeline.process(r.cloud);
  ASSERT_EQ(result.markers.size(), 1u);
  const MarkerResult& m = result.markers[0];
  EXPECT_EQ(m.detection.family, family);
  EXPECT_EQ(m.detection.id, 0);
  EXPECT_EQ(m.corners.size(), 16u);
  // Every lifted chessboard corner against where the truth puts it.
  const Isometry3& truth = r.truth.markers.at(0).T_lidar_marker;
  const std::vector<Vec3> model = marker_frame_keypoints(m.detection, square);
  double worst = 0, sum = 0;
  int lifted = 0;
  for (std::size_t k = 0; k < m.corners.size(); ++k) {
    if (!m.corners[k].valid()) continue;
    const double error = (m.corners[k].point - truth * model[k]).norm();
    worst = std::max(worst, error);
    sum += error;
    ++lifted;
  }
  EXPECT_EQ(lifted, 16);
  ASSERT_TRUE(m.T_lidar_marker);
  const double marker_error = (m.T_lidar_marker->translation() - truth.translation()).norm();
  ASSERT_TRUE(result.pose) << result.pose_missing_reason;
  const eval::CaseScore s = eval::score_frame(result, r.truth);
  std::printf(
      "[ measured ] Mid-40 2.5 m, ChArUco 5x5 of 8 cm: 16 corners mean %.2f mm, max %.2f mm; "
      "board pose %.2f mm; LiDAR %.2f mm %.3f deg (fit rms %.2f mm)\n",
      sum / lifted * 1000, worst * 1000, marker_error * 1000, s.position_error * 1000,
      s.rotation_error_deg, result.pose->rms * 1000);
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(marker_error, 0.005);
  // One 40 cm board: its 0.2 degree tilt error moves the LiDAR by about 9 mm at 2.5 m.
  EXPECT_LT(s.position_error, 0.015);
  EXPECT_LT(s.rotation_error_deg, 0.5);
}

}  // namespace
}  // namespace iilfm::testing
