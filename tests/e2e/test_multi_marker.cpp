// The paper's 35-tag grid on a simulated Mid-40 scan: every tag found, the pose improves with more
// markers, and a marker the map has in the wrong place is rejected, not averaged in.
#include <gtest/gtest.h>

#include "iilfm/eval/case.hpp"
#include "iilfm/sensor.hpp"

namespace iilfm::testing {
namespace {

struct GridScan {
  sim::SceneSetup scene;
  sim::SimResult sim;
};

GridScan grid_scan(std::uint64_t seed) {
  GridScan g{sim::named_scene("grid"), {}};
  sim::SimOptions options;
  options.T_world_lidar = g.scene.T_world_lidar;
  options.frames = 40;
  options.seed = seed;
  g.sim = sim::simulate(g.scene.scene, sim::sensor_model("mid40"), options);
  return g;
}

PipelineOptions mid40_options(MarkerMap map) {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("mid40"), options);
  options.map = std::move(map);
  return options;
}

double position_error(const FrameResult& r, const sim::SimResult& sim) {
  return (r.pose->T_world_lidar.translation() - sim.truth.T_world_lidar.translation()).norm();
}

TEST(MultiMarker, AllGridTagsFoundAndMoreMarkersGiveABetterPose) {
  double error_all = 0, error_one = 0;
  for (std::uint64_t seed : {1, 2, 3}) {
    const GridScan g = grid_scan(seed);
    Pipeline all(mid40_options(eval::map_of(g.scene.scene)));
    const FrameResult& r = all.process(g.sim.cloud);
    EXPECT_EQ(r.markers.size(), 35u) << "seed " << seed;
    for (const MarkerResult& m : r.markers) EXPECT_TRUE(m.in_map) << m.detection.id;
    ASSERT_TRUE(r.pose);
    EXPECT_EQ(r.pose->markers_used.size(), 35u);
    EXPECT_TRUE(r.pose->markers_rejected.empty());
    error_all += position_error(r, g.sim);

    sim::Scene centre_only = g.scene.scene;
    centre_only.markers = {g.scene.scene.markers[17]};
    Pipeline one(mid40_options(eval::map_of(centre_only)));
    const FrameResult& r1 = one.process(g.sim.cloud);
    ASSERT_TRUE(r1.pose);
    EXPECT_EQ(r1.pose->markers_used.size(), 1u);
    error_one += position_error(r1, g.sim);
  }
  std::printf("mean LiDAR position error: 35 markers %.1f mm, centre marker alone %.1f mm\n",
              error_all / 3 * 1000, error_one / 3 * 1000);
  EXPECT_LT(error_all / 3, 0.005);
  EXPECT_LT(error_all, error_one);
}

TEST(MultiMarker, MisMappedMarkerIsRejected) {
  const GridScan g = grid_scan(5);
  sim::Scene wrong = g.scene.scene;
  // The map puts tag 12 one sheet to the side of where it hangs (as if two ids were swapped).
  wrong.markers[12].T_world_marker.translation() += Vec3(0, 0.25, 0);
  Pipeline pipeline(mid40_options(eval::map_of(wrong)));
  const FrameResult& r = pipeline.process(g.sim.cloud);
  ASSERT_TRUE(r.pose) << r.pose_missing_reason;
  ASSERT_EQ(r.pose->markers_rejected.size(), 1u);
  EXPECT_EQ(r.pose->markers_rejected[0].key, "apriltag:tag36h11/12");
  EXPECT_NEAR(r.pose->markers_rejected[0].residual_m, 0.25, 0.02);
  EXPECT_EQ(r.pose->markers_used.size(), 34u);
  EXPECT_LT(position_error(r, g.sim), 0.005);
}

}  // namespace
}  // namespace iilfm::testing
