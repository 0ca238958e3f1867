// End to end on simulated scans: the paper's Mid-40 set-up and LiDARTag's ccw_10m set-up, with each
// sensor's realistic range noise, checked against the simulator's ground truth.
#include <gtest/gtest.h>

#include "sim_case.hpp"

namespace iilfm::testing {
namespace {

void print(const CaseSetup& s, const CaseErrors& e) {
  std::printf(
      "%s/%s frames %d seed %llu: found %d detections %d mean corner %.1f mm max %.1f mm "
      "position %.1f mm rotation %.2f deg, %.2f ms\n",
      s.scene.c_str(), s.sensor.c_str(), s.frames, static_cast<unsigned long long>(s.seed), e.found,
      e.detections, e.mean_corner_error * 1000, e.max_corner_error * 1000, e.position_error * 1000,
      e.rotation_error_deg, e.total_ms);
}

// Paper Table 1, 2 m, 40 integrated Mid-40 frames; issue bounds: corners 3 cm, position 10 cm,
// rotation 6 deg (the paper's worst published errors).
TEST(SimAccuracy, Mid40TagAtTwoMetres) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const CaseSetup setup{"tag-wall", "mid40", 40, seed};
    const CaseErrors e = run_sim_case(setup);
    print(setup, e);
    ASSERT_TRUE(e.found) << "seed " << seed;
    EXPECT_EQ(e.wrong, 0);
    EXPECT_LT(e.mean_corner_error, 0.03);
    ASSERT_TRUE(e.pose);
    EXPECT_LT(e.position_error, 0.10);
    EXPECT_LT(e.rotation_error_deg, 6.0);
  }
}

// Paper Table 3: 32-ring ULTRA Puck, 1.22 m tag16h5 board at 10 m turned 45 deg (paper: 3.3 cm
// mean vertex error, LiDARTag 1.6 cm).
TEST(SimAccuracy, UltraPuckTagAtTenMetres) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const CaseSetup setup{"ccw10m", "ultrapuck", 1, seed};
    const CaseErrors e = run_sim_case(setup);
    print(setup, e);
    ASSERT_TRUE(e.found) << "seed " << seed;
    EXPECT_EQ(e.wrong, 0);
    EXPECT_LT(e.mean_corner_error, 0.03);
    ASSERT_TRUE(e.pose);
    EXPECT_LT(e.position_error, 0.10);
    EXPECT_LT(e.rotation_error_deg, 6.0);
  }
}

}  // namespace
}  // namespace iilfm::testing
