// End to end on simulated scans: the paper's Mid-40 set-up and LiDARTag's ccw_10m set-up, with each
// sensor's realistic range noise, checked against the simulator's ground truth.
#include <gtest/gtest.h>

#include "sim_case.hpp"

namespace iilfm::testing {
namespace {

void print(const CaseSetup& s, const CaseErrors& e) {
  std::printf(
      "%s/%s %s frames %d seed %llu: found %d detections %d mean corner %.1f mm max %.1f mm "
      "position %.1f mm rotation %.2f deg, %.2f ms\n",
      s.scene.c_str(), s.sensor.c_str(), s.lift == LiftMethod::kPaper ? "paper" : "plane", s.frames,
      static_cast<unsigned long long>(s.seed), e.found, e.detections, e.mean_corner_error * 1000,
      e.max_corner_error * 1000, e.position_error * 1000, e.rotation_error_deg, e.total_ms);
}

// Bounds of the foundation issue, the paper's worst published errors: corners 3 cm, LiDAR
// position 10 cm, rotation 6 deg, on every seed.
void expect_within_paper_bounds(const CaseSetup& setup, double max_position_error = 0.10) {
  const CaseErrors e = run_sim_case(setup);
  print(setup, e);
  ASSERT_TRUE(e.found) << "seed " << setup.seed;
  EXPECT_EQ(e.wrong, 0);
  EXPECT_LT(e.mean_corner_error, 0.03);
  ASSERT_TRUE(e.pose);
  EXPECT_LT(e.position_error, max_position_error);
  EXPECT_LT(e.rotation_error_deg, 6.0);
}

// Paper Table 1, 2 m, 40 integrated Mid-40 frames with 2 cm range noise.
TEST(SimAccuracy, Mid40TagAtTwoMetres) {
  for (std::uint64_t seed : {1, 2, 3}) expect_within_paper_bounds({"tag-wall", "mid40", 40, seed});
}

// Paper Table 3: 32-ring ULTRA Puck, 1.22 m tag16h5 board at 10 m turned 45 deg (paper: 3.3 cm
// mean vertex error, LiDARTag 1.6 cm). Measured here: 10-11 mm mean vertex error, rotation
// 0.21-0.29 deg, LiDAR position 2.6-4.5 cm (the normal comes from the coplanar wall around the
// board; from the board alone it was 8-18 cm).
TEST(SimAccuracy, UltraPuckTagAtTenMetres) {
  for (std::uint64_t seed : {1, 2, 3}) expect_within_paper_bounds({"ccw10m", "ultrapuck", 1, seed});
}

// The paper's own lifting on the same scans: it finds the marker and its corners within 3 cm, but
// four corners with 2 cm range noise each leave the rotation (and with it the LiDAR position,
// through the lever arm of the marker distance) far less certain than the plane fit.
TEST(SimAccuracy, PaperLiftingFindsTheCornersWithinThreeCentimetres) {
  for (const char* scene : {"tag-wall", "ccw10m"}) {
    const bool mid40 = std::string(scene) == "tag-wall";
    CaseSetup setup{scene, mid40 ? "mid40" : "ultrapuck", mid40 ? 40 : 1, 1, LiftMethod::kPaper};
    const CaseErrors e = run_sim_case(setup);
    print(setup, e);
    ASSERT_TRUE(e.found);
    EXPECT_LT(e.mean_corner_error, 0.04);
    ASSERT_TRUE(e.pose);
  }
}

}  // namespace
}  // namespace iilfm::testing
