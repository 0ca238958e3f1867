// The LiDAR pose refinement with marker-plane points (`--pose-refine points`) and corner weights
// on the multi-marker maps of `iilfm eval --suite multi`, against the Kabsch pose on the same
// scans: where each helps, where not (so the defaults stay as measured), and that the refined
// pose's covariance still matches its error.
#include <gtest/gtest.h>

#include "iilfm/eval/report.hpp"
#include "iilfm/eval/suite.hpp"
#include "iilfm/option_names.hpp"

namespace iilfm::eval {
namespace {

// Unoptimised (sanitizer) builds run one seed to stay within CI's time; the comparisons are for
// the Release run.
#ifdef NDEBUG
constexpr std::uint64_t kSeeds = 5;
#else
constexpr std::uint64_t kSeeds = 1;
#endif

constexpr std::size_t kGrid = 0, kRoom = 1;

SetupResult run(std::size_t index, PoseRefine refine, bool weight_corners = false) {
  SuiteOptions options;
  options.seeds.clear();
  for (std::uint64_t s = 1; s <= kSeeds; ++s) options.seeds.push_back(s);
  options.lifts = {LiftMethod::kPlane};
  options.tweaks.pose_refine = refine;
  options.tweaks.weight_corners = weight_corners;
  const SuiteResult r = run_suite("multi", {named_suite("multi").at(index)}, options);
  std::cout << "[ measured ] " << to_string(refine) << (weight_corners ? " weighted" : "") << ": "
            << summary_line(r.results.at(0)) << "\n";
  return r.results.at(0);
}

void expect_consistent(const Consistency& c, const char* what) {
  SCOPED_TRACE(what);
  ASSERT_GT(c.count, 0);
#ifdef NDEBUG
  EXPECT_GT(c.ratio(), 0.5) << "claimed sigma too large: " << c.rms_sigma();
  EXPECT_LT(c.ratio(), 2.0) << "claimed sigma too small: " << c.rms_sigma();
#endif
}

TEST(PoseRefine, DefaultsAreTheMeasuredChoice) {
  EXPECT_EQ(LidarPoseOptions{}.refine, PoseRefine::kNone);
  EXPECT_FALSE(LidarPoseOptions{}.weight_corners);
}

// Room (four markers at 2.3-4.5 m on two walls and a box, Avia): the planes' normals pin the
// rotation down. Measured over seeds 1-5: LiDAR rotation 0.0591 -> 0.0412 deg mean (0.0700 ->
// 0.0592 worst), position 3.15 -> 2.77 mm; the refined covariance: position ratio 1.78, rotation
// 1.21 (Kabsch's: 2.7 and 2.0).
TEST(PoseRefine, PlanePointsLowerTheRotationErrorInARoom) {
  const SetupResult refined = run(kRoom, PoseRefine::kPoints);
  ASSERT_EQ(refined.summary.poses, static_cast<int>(kSeeds));
#ifdef NDEBUG  // sanitizer builds run the refinement only, not the comparison
  const SetupResult kabsch = run(kRoom, PoseRefine::kNone);
  ASSERT_EQ(kabsch.summary.poses, static_cast<int>(kSeeds));
  EXPECT_LT(refined.summary.rotation_deg.mean(), 0.8 * kabsch.summary.rotation_deg.mean());
  EXPECT_LT(refined.summary.rotation_deg.worst, kabsch.summary.rotation_deg.worst);
  EXPECT_LT(refined.summary.position.mean(), kabsch.summary.position.mean());
#endif
  expect_consistent(refined.summary.position_claim, "refined LiDAR position");
  expect_consistent(refined.summary.rotation_claim, "refined LiDAR rotation");
}

// The 35-tag grid on one wall (Mid-40, 3.5 m): the corners, spread over 1.5 m, fix the tilt
// better than the markers' planes, whose tilt errs by 4.1-4.4 mrad RMS against 1.85 mrad claimed
// (docs/accuracy.md). Measured over seeds 1-5: Kabsch 0.98 mm / 0.0161 deg, refined 1.32 mm
// / 0.0213 deg, corners weighted 1.18 mm / 0.0191 deg. This is why both stay off by default; the
// refined covariance still covers its error (ratios 1.29 / 1.19).
TEST(PoseRefine, OnACoplanarGridTheCornersAloneAreBest) {
  const SetupResult refined = run(kGrid, PoseRefine::kPoints);
  ASSERT_EQ(refined.summary.poses, static_cast<int>(kSeeds));
#ifdef NDEBUG  // sanitizer builds run the refinement only, not the comparison
  const SetupResult kabsch = run(kGrid, PoseRefine::kNone);
  const SetupResult weighted = run(kGrid, PoseRefine::kNone, true);
  EXPECT_LT(kabsch.summary.position.mean(), 0.0015);
  EXPECT_LT(kabsch.summary.rotation_deg.mean(), 0.025);
  EXPECT_LT(kabsch.summary.position.mean(), refined.summary.position.mean());
  EXPECT_LT(kabsch.summary.position.mean(), weighted.summary.position.mean());
  // Worse, but not by much: the gates keep the planes from dragging the pose.
  EXPECT_LT(refined.summary.position.mean(), 2 * kabsch.summary.position.mean());
  EXPECT_LT(refined.summary.rotation_deg.mean(), 2 * kabsch.summary.rotation_deg.mean());
#endif
  expect_consistent(refined.summary.position_claim, "refined LiDAR position");
  expect_consistent(refined.summary.rotation_claim, "refined LiDAR rotation");
}

}  // namespace
}  // namespace iilfm::eval
