// End to end on simulated scans: the paper's Mid-40 set-up and LiDARTag's ccw_10m set-up, with each
// sensor's realistic range noise, scored against the simulator's ground truth by the eval library.
#include <gtest/gtest.h>

#include "iilfm/eval/case.hpp"

namespace iilfm::testing {
namespace {

eval::CaseScore run(const std::string& scene, const std::string& sensor, std::uint64_t seed,
                    LiftMethod lift) {
  eval::CaseSpec spec;
  spec.scene = scene;
  spec.sensor = sensor;
  const eval::CaseScore s = eval::run_case(eval::simulate_case(spec, seed), lift);
  std::printf(
      "%s/%s %s seed %llu: detected %d/%d mean corner %.1f mm max %.1f mm position %.1f mm "
      "rotation %.2f deg, %.2f ms\n",
      scene.c_str(), sensor.c_str(), eval::lift_name(lift), static_cast<unsigned long long>(seed),
      s.detected, s.visible, s.corner_error_mean * 1000, s.corner_error_max * 1000,
      s.position_error * 1000, s.rotation_error_deg, s.time_ms);
  return s;
}

// Bounds of the foundation issue, the paper's worst published errors: corners 3 cm, LiDAR
// position 10 cm, rotation 6 deg, on every seed.
void expect_within_paper_bounds(const std::string& scene, const std::string& sensor,
                                std::uint64_t seed) {
  const eval::CaseScore e = run(scene, sensor, seed, LiftMethod::kPlane);
  ASSERT_EQ(e.detected, 1) << "seed " << seed;
  EXPECT_EQ(e.false_positives + e.wrong_ids, 0);
  EXPECT_LT(e.corner_error_mean, 0.03);
  ASSERT_TRUE(e.pose);
  EXPECT_LT(e.position_error, 0.10);
  EXPECT_LT(e.rotation_error_deg, 6.0);
}

// Paper Table 1, 2 m, 40 integrated Mid-40 frames with 2 cm range noise. Measured: corners
// 0.2-0.4 mm, position 1.8-3.1 mm, rotation 0.08-0.10 deg.
TEST(SimAccuracy, Mid40TagAtTwoMetres) {
  for (std::uint64_t seed : {1, 2, 3}) expect_within_paper_bounds("tag-wall", "mid40", seed);
}

// Paper Table 3: 32-ring ULTRA Puck, 1.22 m tag16h5 board at 10 m turned 45 deg (paper: 3.3 cm
// mean vertex error, LiDARTag 1.6 cm). Measured here: 3-4 mm mean vertex error, rotation
// 0.21-0.29 deg, LiDAR position 2.6-4.5 cm (the normal comes from the coplanar wall around the
// board; from the board alone it was 8-18 cm). Issue 4's target: vertex error <= 1 cm.
TEST(SimAccuracy, UltraPuckTagAtTenMetres) {
  for (std::uint64_t seed : {1, 2, 3}) {
    expect_within_paper_bounds("ccw10m", "ultrapuck", seed);
    EXPECT_LT(run("ccw10m", "ultrapuck", seed, LiftMethod::kPlane).corner_error_mean, 0.01);
  }
}

// The paper's own lifting on the same scans: it finds the marker and its corners within a few
// centimetres, but four corners with 2 cm range noise each leave the rotation (and with it the
// LiDAR position, through the lever arm of the marker distance) far less certain than the plane
// fit.
TEST(SimAccuracy, PaperLiftingFindsTheCornersWithinThreeCentimetres) {
  for (const char* scene : {"tag-wall", "ccw10m"}) {
    const bool mid40 = std::string(scene) == "tag-wall";
    const eval::CaseScore e = run(scene, mid40 ? "mid40" : "ultrapuck", 1, LiftMethod::kPaper);
    ASSERT_EQ(e.detected, 1);
    EXPECT_LT(e.corner_error_mean, 0.04);
    ASSERT_TRUE(e.pose);
  }
}

}  // namespace
}  // namespace iilfm::testing

namespace iilfm::testing {
namespace {

// Known-size refinement: with the size from the map, the reported corners are the best square of
// that size, which averages the four corners' independent errors. ULTRA Puck at 10 m, each seed
// at its own sub-pixel placement (jitter_px), its lasers at the manual's azimuth offsets: measured
// 16.8 mm mean vertex error as lifted, 6.9 mm after the fit (seeds 1-3); over 16 seeds 16.1 and
// 6.0 mm (with every ring on the column grid, as the simulator once fired them: 13.0 and 6.7).
TEST(SimAccuracy, KnownSizeSquareFitTightensTheVertices) {
  double lifted = 0, fitted = 0;
  for (std::uint64_t seed : {1, 2, 3}) {
    eval::CaseSpec spec;
    spec.scene = "ccw10m";
    spec.sensor = "ultrapuck";
    spec.jitter_px = 1;
    const eval::SimulatedCase c = eval::simulate_case(spec, seed);
    PipelineOptions options = eval::pipeline_options_for(c, LiftMethod::kPlane);
    options.fit_known_size = false;
    Pipeline raw(options);
    const eval::CaseScore raw_score = eval::score_frame(raw.process(c.scan.cloud), c.scan.truth);
    options.fit_known_size = true;
    Pipeline square(options);
    const FrameResult& r = square.process(c.scan.cloud);
    const eval::CaseScore square_score = eval::score_frame(r, c.scan.truth);
    ASSERT_EQ(r.markers.size(), 1u);
    const auto& corners = r.markers[0].corners;
    const double size = c.setup.scene.markers[0].size_m;
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR((corners[(k + 1) % 4].point - corners[k].point).norm(), size, 1e-9);
    EXPECT_GT(r.markers[0].marker_fit_rms, 0.0);  // the lifted corners were not a perfect square
    EXPECT_NEAR(square_score.position_error, raw_score.position_error, 1e-9);  // same pose
    lifted += raw_score.corner_error_mean / 3;
    fitted += square_score.corner_error_mean / 3;
  }
  std::printf("ULTRA Puck 10 m mean vertex error: lifted %.1f mm, square fit %.1f mm\n",
              lifted * 1000, fitted * 1000);
  EXPECT_LT(fitted, 0.009);
  EXPECT_LT(fitted, 0.6 * lifted);
}

}  // namespace
}  // namespace iilfm::testing
