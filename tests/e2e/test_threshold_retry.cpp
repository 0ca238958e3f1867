// PipelineOptions::retry_with_otsu: print whose black and white both return above a preset's fixed
// threshold (40 on the Velodyne and Livox scales) shows no marker at that threshold; the frame is
// thresholded at Otsu's as well, and the markers it shows are reported with where they came from.
#include <gtest/gtest.h>

#include <cmath>

#include "iilfm/eval/case.hpp"
#include "iilfm/option_names.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/sim/scenes.hpp"
#include "iilfm/sim/simulate.hpp"

namespace iilfm {
namespace {

// A 60 cm tag36h11 on the tag wall 2 m ahead of a VLP-16, printed so that its ink returns `black`
// and its paper `white`.
sim::SimResult vlp16_tag(float white, float black) {
  sim::SceneParams params;
  params.marker_size_m = 0.6;
  sim::SceneSetup setup = sim::named_scene("tag-wall", params);
  setup.scene.white_intensity = white;
  setup.scene.black_intensity = black;
  sim::SimOptions options;
  options.T_world_lidar = setup.T_world_lidar;
  options.seed = 2;
  return sim::simulate(setup.scene, sim::sensor_model("vlp16"), options);
}

PipelineOptions vlp16_preset() {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("vlp16"), options);
  return options;
}

TEST(ThresholdRetry, PrintAboveThePresetsThresholdIsFoundAtOtsus) {
  const sim::SimResult scan = vlp16_tag(200, 60);
  PipelineOptions options = vlp16_preset();
  ASSERT_EQ(options.preprocess.threshold, 40.0);

  options.retry_with_otsu = false;
  Pipeline without(options);
  const FrameResult& missed = without.process(scan.cloud);
  EXPECT_TRUE(missed.markers.empty());
  EXPECT_FALSE(missed.threshold_retry);

  options.retry_with_otsu = true;
  Pipeline with(options);
  const FrameResult& r = with.process(scan.cloud);
  ASSERT_EQ(r.markers.size(), 1u);
  EXPECT_EQ(r.markers[0].detection.id, 0);
  ASSERT_TRUE(r.threshold_retry);
  EXPECT_EQ(r.threshold_retry->fixed, 40.0);
  EXPECT_EQ(r.threshold_retry->found, 1u);
  // Otsu's threshold lies between the ink and the paper, and it is the one reported as applied.
  EXPECT_GT(r.threshold_retry->otsu, 60.0);
  EXPECT_LT(r.threshold_retry->otsu, 200.0);
  EXPECT_EQ(r.preprocessed.threshold, r.threshold_retry->otsu);
  // The corners lie on the truth's to a few centimetres (a VLP-16's 2-degree rows at 2 m).
  for (int k = 0; k < 4; ++k) {
    const LiftedCorner& corner = r.markers[0].corners[static_cast<std::size_t>(k)];
    ASSERT_TRUE(corner.valid());
    EXPECT_LT(
        (corner.point - scan.truth.markers[0].corners_lidar[static_cast<std::size_t>(k)]).norm(),
        0.05)
        << "corner " << k;
  }
}

TEST(ThresholdRetry, TheUsersThresholdAndAFoundMarkerAreNotRetried) {
  // The user's own 40: kept, so the marker stays unseen.
  const sim::SimResult bright = vlp16_tag(200, 60);
  PipelineOptions given = vlp16_preset();
  set_threshold("40", given);
  Pipeline kept(given);
  const FrameResult& r = kept.process(bright.cloud);
  EXPECT_TRUE(r.markers.empty());
  EXPECT_FALSE(r.threshold_retry);

  // The print the preset expects: found at its threshold, no second look.
  const sim::SimResult usual = vlp16_tag(120, 10);
  Pipeline preset(vlp16_preset());
  const FrameResult& found = preset.process(usual.cloud);
  ASSERT_EQ(found.markers.size(), 1u);
  EXPECT_FALSE(found.threshold_retry);
  EXPECT_EQ(found.preprocessed.threshold, 40.0);
}

TEST(ThresholdRetry, OnlyAnOtsuThresholdFarFromTheFixedOneIsTried) {
  // No marker of the family asked for; Otsu's threshold of this image, then fixed thresholds
  // within and beyond a quarter of their own value from it.
  const sim::SimResult scan = vlp16_tag(120, 10);
  PipelineOptions options = vlp16_preset();
  options.families = {"apriltag:tag16h5"};
  const double otsu = otsu_threshold(Pipeline(options).process(scan.cloud).preprocessed);
  ASSERT_GT(otsu, 10.0);

  options.preprocess.threshold = 0.9 * otsu;
  Pipeline near(options);
  EXPECT_FALSE(near.process(scan.cloud).threshold_retry);

  options.preprocess.threshold = 0.5 * otsu;
  Pipeline far(options);
  const FrameResult& r = far.process(scan.cloud);
  ASSERT_TRUE(r.threshold_retry);
  EXPECT_DOUBLE_EQ(r.threshold_retry->otsu, otsu);
  EXPECT_EQ(r.threshold_retry->found, 0u);
  EXPECT_EQ(r.preprocessed.threshold, 0.5 * otsu);  // nothing found: the fixed one stays applied
}

// A 40 cm tag36h11 13 m from a Livox Horizon, beam footprints on: the 0.28 deg vertical divergence
// spans 1.3 of its 5 cm cells and averages black into white, which the preset's threshold of 40
// (print at 10 and 120) turns white. The local threshold splits them, on the second look only.
TEST(ThresholdRetry, ALivoxPresetLooksAgainLocallyWhereTheBeamBlursAFarMarker) {
  eval::CaseSpec spec = eval::tag_wall_spec("horizon", 13, 0.4);
  spec.physics.footprint = true;
  spec.lidar_rpy_deg = Vec3(0, 1, 1.7);
  const eval::SimulatedCase c = eval::simulate_case(spec, 1);
  PipelineOptions options = eval::pipeline_options_for(c, LiftMethod::kPlane);
  ASSERT_TRUE(options.retry_with_local_threshold);

  options.retry_with_local_threshold = false;
  Pipeline without(options);
  const FrameResult& missed = without.process(c.scan.cloud);
  EXPECT_TRUE(missed.markers.empty());
  EXPECT_FALSE(missed.threshold_retry);  // Otsu's threshold lies within a quarter of 40

  options.retry_with_local_threshold = true;
  Pipeline with(options);
  const FrameResult& r = with.process(c.scan.cloud);
  ASSERT_EQ(r.markers.size(), 1u);
  EXPECT_EQ(r.markers[0].detection.id, 0);
  ASSERT_TRUE(r.threshold_retry);
  EXPECT_TRUE(r.threshold_retry->local);
  EXPECT_EQ(r.threshold_retry->fixed, 40.0);
  EXPECT_EQ(r.threshold_retry->found, 1u);
  EXPECT_EQ(r.preprocessed.threshold, 40.0);  // still the flat regions' threshold
  for (int k = 0; k < 4; ++k) {
    const LiftedCorner& corner = r.markers[0].corners[static_cast<std::size_t>(k)];
    ASSERT_TRUE(corner.valid());
    EXPECT_LT(
        (corner.point - c.scan.truth.markers[0].corners_lidar[static_cast<std::size_t>(k)]).norm(),
        0.03)
        << "corner " << k;
  }

  // The user's own threshold is kept: no second look.
  set_threshold("40", options);
  EXPECT_FALSE(options.retry_with_local_threshold);
}

}  // namespace
}  // namespace iilfm
