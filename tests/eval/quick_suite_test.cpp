// The quick suite (one set-up of each paper table and an ArUco case) holds the accuracy measured
// when it was written, with margins, so regressions fail. Bounds: about twice the measured mean and
// worst over seeds 1-3, never looser than the (Mid-40: LiDAR position 10 cm, rotation 6
// deg) or than tests/e2e/test_sim_accuracy.cpp. Each seed places the LiDAR at its own sub-pixel
// yaw and pitch (SuiteOptions::jitter_px), so the figures are over placements, not one.
#include <gtest/gtest.h>

#include "iilfm/eval/report.hpp"
#include "iilfm/eval/suite.hpp"

namespace iilfm::eval {
namespace {

// Unoptimised (sanitizer) builds run one seed to stay within CI's time.
#ifdef NDEBUG
const std::vector<std::uint64_t> kSeeds = {1, 2, 3};
#else
const std::vector<std::uint64_t> kSeeds = {1};
#endif

struct Bounds {
  double corner_mean, corner_worst;      // metres
  double position_mean, position_worst;  // metres
  double rotation_mean, rotation_worst;  // degrees
};

// Runs set-up `index` of the quick suite with both lifting methods on the same scans.
std::vector<SetupResult> run_quick_setup(std::size_t index) {
  SuiteOptions options;
  options.seeds = kSeeds;
  const SuiteResult r = run_suite("quick", {named_suite("quick").at(index)}, options);
  for (const SetupResult& s : r.results) std::cout << "[ measured ] " << summary_line(s) << "\n";
  return r.results;
}

void expect_within(const SetupResult& r, const Bounds& b) {
  const Summary& s = r.summary;
  SCOPED_TRACE(summary_line(r));
  EXPECT_EQ(s.detected, s.cases);
  EXPECT_EQ(s.visible, s.cases);
  EXPECT_EQ(s.false_positives, 0);
  EXPECT_EQ(s.wrong_ids, 0);
  ASSERT_EQ(s.poses, s.cases);
  EXPECT_LT(s.corner_error.mean(), b.corner_mean);
  EXPECT_LT(s.corner_error.worst, b.corner_worst);
  EXPECT_LT(s.position.mean(), b.position_mean);
  EXPECT_LT(s.position.worst, b.position_worst);
  EXPECT_LT(s.rotation_deg.mean(), b.rotation_mean);
  EXPECT_LT(s.rotation_deg.worst, b.rotation_worst);
}

// Paper Table 1 at 2 m, 40 frames. Measured (seeds 1-3), plane: vertex 0.5 mm (worst 0.7),
// position 1.7 mm (2.3), rotation 0.20 deg (0.27); paper's rule: vertex 5.8 mm (17.6), position
// 123 mm (182), rotation 3.5 deg (5.2).
TEST(QuickSuite, Mid40AtTwoMetres) {
  const std::vector<SetupResult> r = run_quick_setup(0);
  ASSERT_EQ(r.size(), 2u);
  expect_within(r[0], {0.0016, 0.003, 0.005, 0.0065, 0.4, 0.55});
  expect_within(r[1], {0.017, 0.04, 0.40, 0.50, 11, 14});
  EXPECT_LT(r[0].summary.rotation_deg.mean() * 5, r[1].summary.rotation_deg.mean());
}

// Paper Table 2, LiDAR yawed +15 deg. Measured, plane: vertex 0.5 mm (0.8), position 2.9 mm (4.3),
// rotation 0.19 deg (0.26); paper's rule: 15.0 mm (36.7), 214 mm (301), 6.1 deg (8.6).
TEST(QuickSuite, Mid40YawedFifteenDegrees) {
  const std::vector<SetupResult> r = run_quick_setup(1);
  ASSERT_EQ(r.size(), 2u);
  expect_within(r[0], {0.0018, 0.003, 0.006, 0.009, 0.3, 0.35});
  expect_within(r[1], {0.026, 0.05, 0.50, 0.62, 14, 18});
}

// Paper Table 3, ccw10m, the lasers at the VLP-32C manual's azimuth offsets. Measured, plane:
// vertex 6.9 mm (8.6), position 40 mm (63), rotation 0.46 deg (0.68); paper's rule: 31.5 mm
// (66.5), 384 mm (735), 2.38 deg (4.23). Over 16 seeds, plane: rotation 0.38 deg (0.88); with
// every ring on the column grid (the simulator before the offsets) 0.47 deg (1.02), and seeds 1-3
// 0.36 deg (0.47). Seed 1 alone (the sanitizer builds' run): 0.68 deg.
TEST(QuickSuite, UltraPuckCcw10m) {
  const std::vector<SetupResult> r = run_quick_setup(2);
  ASSERT_EQ(r.size(), 2u);
  expect_within(r[0], {0.021, 0.03, 0.07, 0.09, 0.8, 1.0});
  expect_within(r[1], {0.04, 0.08, 0.55, 1.0, 3.2, 5.8});
}

// The paper's grid ArUco marker (16 cm DICT_4X4_50) alone at 2 m, 40 frames. Measured (seeds
// 1-3), plane: vertex 0.3 mm (0.4), position 1.9 mm (2.5), rotation 0.07 deg (0.08); paper's rule:
// 12.7 mm (26.2), 196 mm (257), 5.6 deg (7.4).
TEST(QuickSuite, Mid40ArucoAtTwoMetres) {
  const std::vector<SetupResult> r = run_quick_setup(3);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].setup.spec.scene_params.family, "aruco:DICT_4X4_50");
  expect_within(r[0], {0.0005, 0.001, 0.006, 0.008, 0.17, 0.25});
  expect_within(r[1], {0.03, 0.055, 0.55, 0.66, 15, 19});
}

}  // namespace
}  // namespace iilfm::eval
