// Families beyond the square tag on simulated scans: AprilTag's circle families lifted and posed
// through their data-grid corners, and one report when two back-ends decode the same tag.
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
  TwoBackEnds t = tag_seen_by_two_back_ends(
      "aruco:DICT_APRILTAG_36h11", {"apriltag:tag36h11", "aruco:DICT_APRILTAG_36h11"});
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

}  // namespace
}  // namespace iilfm::testing
