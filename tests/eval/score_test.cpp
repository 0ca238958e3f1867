// Scoring against the truth: a correct detection, a wrong id and a detection off every marker are
// told apart, and the errors are the distances to the true corners and poses.
#include <gtest/gtest.h>

#include "iilfm/eval/case.hpp"

namespace iilfm::eval {
namespace {

// One noise-free Mid-40 scan of the paper's tag, shared by the tests (simulated once).
const SimulatedCase& paper_scan() {
  static const SimulatedCase c = [] {
    CaseSpec spec;
    spec.physics.range_sigma_m = 0;
    spec.physics.intensity_sigma = 0;
    return simulate_case(spec, 1);
  }();
  return c;
}

FrameResult detect(const SimulatedCase& c) {
  Pipeline pipeline(pipeline_options_for(c, LiftMethod::kPlane));
  return pipeline.process(c.scan.cloud);
}

TEST(Score, TheTagIsFoundWithErrorsMatchingTheTruth) {
  const FrameResult result = detect(paper_scan());
  ASSERT_EQ(result.markers.size(), 1u);
  const CaseScore s = score_frame(result, paper_scan().scan.truth);
  EXPECT_EQ(s.visible, 1);
  EXPECT_EQ(s.detected, 1);
  EXPECT_EQ(s.false_positives, 0);
  EXPECT_EQ(s.wrong_ids, 0);
  EXPECT_EQ(s.corners, 4);
  EXPECT_EQ(s.marker_poses, 1);
  ASSERT_TRUE(s.pose);
  // By hand: the distance of corner 0 from the truth is part of the mean.
  const double e0 =
      (result.markers[0].corners[0].point - paper_scan().scan.truth.markers[0].corners_lidar[0])
          .norm();
  EXPECT_LE(e0, s.corner_error_max + 1e-12);
  EXPECT_GT(s.time_ms, 0);
}

TEST(Score, AnotherIdOnTheMarkerIsAWrongIdAndADetectionElsewhereAFalsePositive) {
  FrameResult result = detect(paper_scan());
  ASSERT_EQ(result.markers.size(), 1u);
  MarkerResult wrong = result.markers[0];
  wrong.detection.id = 7;
  MarkerResult elsewhere = result.markers[0];
  for (Vec2& p : elsewhere.detection.corners_px) p += Vec2(200, 0);
  result.markers.push_back(wrong);
  result.markers.push_back(elsewhere);
  result.markers.push_back(result.markers[0]);  // the same marker reported twice
  const CaseScore s = score_frame(result, paper_scan().scan.truth);
  EXPECT_EQ(s.detected, 1);
  EXPECT_EQ(s.wrong_ids, 1);
  EXPECT_EQ(s.false_positives, 2);
}

// A full-circle image: the marker behind the LiDAR straddles the seam, its corners at both ends of
// the image. Its footprint must wrap, not span the whole image and claim every detection.
TEST(Score, AMarkerAcrossTheSeamOfAFullCircleIsScoredWhereItIs) {
  CaseSpec spec;
  spec.scene = "around";
  spec.sensor = "os1-64";
  spec.frames = 1;
  const SimulatedCase c = simulate_case(spec, 1);
  const FrameResult result = detect(c);
  const CaseScore s = score_frame(result, c.scan.truth);
  EXPECT_GE(s.detected, 4);
  EXPECT_EQ(s.wrong_ids, 0);
  EXPECT_EQ(s.false_positives, 0);
  bool seam = false;
  for (const MarkerResult& m : result.markers)
    for (const Vec2& p : m.detection.corners_px) seam |= p.x() >= result.image.geometry.width;
  EXPECT_TRUE(seam) << "no detection crosses the seam: the test checks too little";
}

TEST(Score, NoDetectionNoPoseNoErrors) {
  FrameResult result = detect(paper_scan());
  result.markers.clear();
  result.pose.reset();
  const CaseScore s = score_frame(result, paper_scan().scan.truth);
  EXPECT_EQ(s.visible, 1);
  EXPECT_EQ(s.detected, 0);
  EXPECT_EQ(s.corners, 0);
  EXPECT_FALSE(s.pose);
}

// Through the whole pipeline a noise-free scan lands every corner within one pixel's footprint:
// at 2 m a 0.05 deg pixel spans 1.75 mm.
TEST(Score, NoiseFreeMid40CornersWithinOnePixelFootprint) {
  const CaseScore plane = run_case(paper_scan(), LiftMethod::kPlane);
  std::printf(
      "[ measured ] noise-free Mid-40 at 2 m, plane lift: corner mean %.2f mm, max %.2f mm, "
      "LiDAR position %.2f mm, rotation %.3f deg\n",
      plane.corner_error_mean * 1000, plane.corner_error_max * 1000, plane.position_error * 1000,
      plane.rotation_error_deg);
  ASSERT_EQ(plane.detected, 1);
  EXPECT_EQ(plane.corners, 4);
  EXPECT_LT(plane.corner_error_max, 2.0 * std::tan(0.05 * M_PI / 180));
}

TEST(Score, InvalidPointsAreDroppedBeforeDetection) {
  CaseSpec spec;
  spec.physics.invalid_fraction = 0.2;
  const SimulatedCase c = simulate_case(spec, 2);
  for (std::size_t i = 0; i < c.scan.cloud.size(); ++i) {
    ASSERT_TRUE(std::isfinite(c.scan.cloud.x[i]));
    ASSERT_FALSE(c.scan.cloud.x[i] == 0 && c.scan.cloud.y[i] == 0 && c.scan.cloud.z[i] == 0);
  }
  EXPECT_EQ(c.scan.cloud.time.size(), c.scan.cloud.size());
  EXPECT_EQ(run_case(c, LiftMethod::kPlane).detected, 1);
}

TEST(Score, SensorsWithoutAPresetGetTheirOwnResolution) {
  CaseSpec spec;
  spec.sensor = "os1-64";
  spec.scene_params.marker_size_m = 0.8;
  const SimulatedCase c = simulate_case(spec, 1);
  const PipelineOptions o = pipeline_options_for(c, LiftMethod::kPlane);
  // A preset of that name, should iilfm gain one, would be the sensor's own figures too.
  EXPECT_NEAR(o.projection.res_h_deg, 360.0 / 1024, 0.001);
  EXPECT_NEAR(o.projection.res_v_deg, 45.0 / 63, 0.01);
  EXPECT_GT(c.scan.cloud.size(), 10000u);
}

}  // namespace
}  // namespace iilfm::eval
