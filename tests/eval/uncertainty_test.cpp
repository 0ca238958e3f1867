// The covariances iilfm reports must match the errors it makes: over simulated seeds, the RMS of
// the observed error over the RMS of the claimed sigma stays near 1 (a sigma covers the error about
// as often as a sigma should), for the marker poses and for the LiDAR pose.
#include <gtest/gtest.h>

#include "iilfm/eval/report.hpp"
#include "iilfm/eval/suite.hpp"

namespace iilfm::eval {
namespace {

// Unoptimised (sanitizer) builds run fewer seeds to stay within CI's time; the check itself is
// for the Release run.
#ifdef NDEBUG
constexpr std::uint64_t kSeeds = 16;
#else
constexpr std::uint64_t kSeeds = 1;
#endif

SetupResult run_setup(std::size_t index, const std::string& suite = "quick") {
  SuiteOptions options;
  options.seeds.clear();
  for (std::uint64_t s = 1; s <= kSeeds; ++s) options.seeds.push_back(s);
  options.lifts = {LiftMethod::kPlane};
  const SuiteResult r = run_suite(suite, {named_suite(suite).at(index)}, options);
  std::cout << "[ measured ] " << summary_line(r.results.at(0)) << "\n" << uncertainty_markdown(r);
  return r.results.at(0);
}

// `lowest`: how conservative a claim may be (error / claimed sigma); over-confident claims (ratio
// above 2) always fail.
void expect_consistent(const Consistency& c, const char* what, double lowest = 0.5) {
  SCOPED_TRACE(what);
  ASSERT_GT(c.count, 0);
  EXPECT_GT(c.rms_sigma(), 0);
#ifdef NDEBUG
  EXPECT_GT(c.ratio(), lowest) << "claimed sigma too large: " << c.rms_sigma();
  EXPECT_LT(c.ratio(), 2.0) << "claimed sigma too small: " << c.rms_sigma();
#endif
}

TEST(Uncertainty, Mid40AtTwoMetresClaimsTheErrorItMakes) {
  const SetupResult r = run_setup(0);
  // At 2 m the Mid-40 marker's position claim runs about 2x conservative (the edges' quantisation
  // term, cut by the square root of about 4 points per pixel, still claims more than the dense
  // rosette centre's sub-pixel edges err): safe, so allowed down to 0.4.
  expect_consistent(r.summary.marker_position_claim, "marker position", 0.4);
  expect_consistent(r.summary.marker_rotation_claim, "marker rotation");
  expect_consistent(r.summary.position_claim, "LiDAR position");
  expect_consistent(r.summary.rotation_claim, "LiDAR rotation");
}

// The marker position claim runs about 2x conservative (measured 0.48, 16 seeds): the edges'
// quantisation term counts the pixel phases an edge crosses on one column grid, but the VLP-32C's
// lasers fire at their own offsets, so its rings sample an edge at phases of their own and
// average the quantisation further (above 0.5 while the simulator fired every ring on the grid):
// safe, so allowed down to 0.4.
TEST(Uncertainty, UltraPuckAtTenMetresClaimsTheErrorItMakes) {
  const SetupResult r = run_setup(2);
  expect_consistent(r.summary.marker_position_claim, "marker position", 0.4);
  expect_consistent(r.summary.marker_rotation_claim, "marker rotation");
  expect_consistent(r.summary.position_claim, "LiDAR position");
  expect_consistent(r.summary.rotation_claim, "LiDAR rotation");
}

// Five markers around an OS1-64 on four walls, one sweep: every edge sits on the sensor's fixed
// grid. Before the edges' quantisation entered the corners' covariance the LiDAR position was
// under-claimed 3.3x (10 seeds, one placement for all).
TEST(Uncertainty, MarkersAroundASpinningLidarClaimTheErrorTheyMake) {
  const SetupResult r = run_setup(2, "multi");
  expect_consistent(r.summary.position_claim, "LiDAR position");
  expect_consistent(r.summary.rotation_claim, "LiDAR rotation");
}

}  // namespace
}  // namespace iilfm::eval
