// Intensity normalisation against the simulator's ground truth: with raw intensity (reflectivity
// x cos(incidence) x (10 m / range)^2, SimOptions::IntensityModel::kRaw) the normalised image
// gives back each surface's reflectivity, and one threshold finds markers at 2 m and far away,
// also both in one scan, only with normalisation. Marker coverage grows with Livox integration.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "iilfm/error.hpp"
#include "iilfm/eval/case.hpp"
#include "iilfm/eval/intensity_study.hpp"
#include "iilfm/marker_coverage.hpp"
#include "iilfm/option_names.hpp"
#include "iilfm/report.hpp"
#include "iilfm/sim/physics_request.hpp"

namespace iilfm {
namespace {

eval::SimulatedCase raw_case(const std::string& sensor, double distance, double size,
                             std::uint64_t seed) {
  eval::CaseSpec spec = eval::tag_wall_spec(sensor, distance, size);
  spec.physics.intensity_model = sim::SimOptions::IntensityModel::kRaw;
  return eval::simulate_case(spec, seed);
}

double median(std::vector<float> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// The wall (reflectivity 60, about 6 m ahead, seen up to 45 deg off) and the floor (25, seen at
// grazing angles) in the normalised image, against the truth.
TEST(IntensityNormalisationSim, NormalisedImageGivesBackTheSurfacesReflectivity) {
  const eval::SimulatedCase c = raw_case("os1-128", 6, 1.0, 3);
  auto levels = [&](IntensityNormalisation mode, double& wall, double& floor) {
    PipelineOptions options = eval::pipeline_options_for(c, LiftMethod::kPlane);
    options.preprocess.normalise.mode = mode;
    Pipeline pipeline(options);
    const FrameResult& r = pipeline.process(c.scan.cloud);
    const cv::Mat& values =
        mode == IntensityNormalisation::kNone ? r.image.intensity : r.preprocessed.normalised;
    std::vector<float> on_wall, on_floor;
    const double floor_z = -c.setup.T_world_lidar.translation().z();
    for (int row = 0; row < r.image.index.rows; ++row)
      for (int col = 0; col < r.image.index.cols; ++col) {
        const int i = r.image.index.at<int>(row, col);
        if (i < 0) continue;
        const Vec3 p = c.scan.cloud.point(static_cast<std::size_t>(i));
        // Away from the marker's sheet and from the wall-floor corner (mixed windows).
        if (std::abs(p.z() - floor_z) < 0.05 && p.x() < 4.5)
          on_floor.push_back(values.at<float>(row, col));
        else if (p.x() > 5.9 && std::abs(p.y()) > 1.2 && p.z() - floor_z > 0.5)
          on_wall.push_back(values.at<float>(row, col));
      }
    ASSERT_GT(on_wall.size(), 1000u);
    ASSERT_GT(on_floor.size(), 1000u);
    wall = median(on_wall);
    floor = median(on_floor);
    std::printf("%s: wall %.1f floor %.1f\n", to_string(mode), wall, floor);
  };
  double wall = 0, floor = 0;
  levels(IntensityNormalisation::kNone, wall, floor);
  // Raw (measured 126 and 81): the wall at 6 m twice its reflectivity, the near floor over 3x.
  EXPECT_GT(wall, 100);
  EXPECT_GT(floor, 60);
  levels(IntensityNormalisation::kRange, wall, floor);
  EXPECT_NEAR(wall, 60 * 0.9, 60 * 0.12);  // the wall's median is seen about 25 deg off
  EXPECT_LT(floor, 25 * 0.6);              // the floor's grazing cosine is left in (measured 7.2)
  levels(IntensityNormalisation::kRangeIncidence, wall, floor);
  EXPECT_NEAR(wall, 60, 60 * 0.05);  // measured 59.9
  EXPECT_NEAR(floor, 25, 25 * 0.1);  // measured 25.1
}

eval::IntensityQuery query(const std::string& sensor, double size, std::vector<double> distances) {
  eval::IntensityQuery q;
  q.sensor = sensor;
  q.marker_size_m = size;
  q.distances = std::move(distances);
  q.seeds = 3;
  q.variants = {{"fixed 40", "40", "none"},
                {"fixed 1000", "1000", "none"},
                {"otsu", "otsu", "none"},
                {"fixed 40 + range", "40", "range"},
                {"otsu + range", "otsu", "range"}};
  return q;
}

TEST(IntensityNormalisationSim, OneFixedThresholdServes2mAnd12mOnlyWhenNormalised) {
#ifndef NDEBUG
  // Sanitizer builds simulate 20-40x slower (over 500 s here): the study's code runs in the other
  // tests of this file and in tests/core/test_intensity_normalisation.cpp under the sanitizers.
  GTEST_SKIP() << "the intensity study runs in optimised builds only";
#endif
  const eval::IntensityQuery q = query("os1-128", 1.0, {2, 12});
  const std::vector<eval::IntensityResult> r = eval::intensity_study(q);
  // found[0] = 2 m, found[1] = 12 m, of 3 seeds.
  EXPECT_EQ(r[0].found[0].second, 0);  // 40 raw: the black print at 2 m returns 250
  EXPECT_EQ(r[1].found[1].second, 0);  // 1000 (between black and white at 2 m) misses at 12 m
  EXPECT_EQ(r[1].found[0].second, 3);
  EXPECT_EQ(r[3].found[0].second, 3);  // 40 normalised: both
  EXPECT_GE(r[3].found[1].second, 2);
  for (const eval::IntensityResult& v : r) {
    EXPECT_EQ(v.false_positives, 0) << v.variant.name;
    EXPECT_EQ(v.empty_scene_detections, 0) << v.variant.name;
  }
}

TEST(IntensityNormalisationSim, OneImageWithMarkersAt2mAnd8mNeedsNormalisation) {
#ifndef NDEBUG
  // Sanitizer builds simulate 20-40x slower (over 500 s here): the study's code runs in the other
  // tests of this file and in tests/core/test_intensity_normalisation.cpp under the sanitizers.
  GTEST_SKIP() << "the intensity study runs in optimised builds only";
#endif
  eval::IntensityQuery q = query("os1-128", 1.0, {8});
  q.near_m = 2;
  const std::vector<eval::IntensityResult> r = eval::intensity_study(q);
  EXPECT_EQ(r[0].found_both[0], 0);
  EXPECT_EQ(r[1].found_both[0], 0);
  EXPECT_EQ(r[2].found_both[0], 0);  // Otsu: one threshold for the whole raw image fails too
  EXPECT_EQ(r[3].found_both[0], 3);
  EXPECT_EQ(r[4].found_both[0], 3);
}

TEST(IntensityNormalisationSim, OnlyTheOusterPresetsNormaliseByDefault) {
  for (const SensorPreset& preset : sensor_presets())
    EXPECT_EQ(preset.normalise, preset.name.rfind("os", 0) == 0
                                    ? IntensityNormalisation::kRangeIncidence
                                    : IntensityNormalisation::kNone)
        << preset.name;
}

TEST(IntensityNormalisationSim, NormalisationIsOffWithoutAsking) {
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("vlp16"), options);
  EXPECT_EQ(options.preprocess.normalise.mode, IntensityNormalisation::kNone);
  set_intensity_normalisation("range", options);  // the preset's 40 was in reported units
  EXPECT_EQ(options.preprocess.normalise.mode, IntensityNormalisation::kRange);
  EXPECT_FALSE(options.preprocess.threshold.has_value());
  set_threshold("40", options);  // now in normalised units
  EXPECT_EQ(*options.preprocess.threshold, 40);
  EXPECT_THROW(set_intensity_normalisation("incidence", options), InputError);
}

// Coverage: the share of the marker's pixels holding a point grows with Livox integration, and a
// spinning LiDAR with ring rows measures nearly every pixel of its marker.
TEST(MarkerCoverageSim, GrowsWithIntegrationAndIsInTheJson) {
  double coverage[2] = {0, 0};
  const int frames[2] = {10, 60};
  for (int k = 0; k < 2; ++k) {
    eval::CaseSpec spec;
    spec.scene = "tag-wall";
    spec.sensor = "mid40";
    spec.frames = frames[k];
    const eval::SimulatedCase c = eval::simulate_case(spec, 2);
    Pipeline pipeline(eval::pipeline_options_for(c, LiftMethod::kPlane));
    const FrameResult& r = pipeline.process(c.scan.cloud);
    ASSERT_EQ(r.markers.size(), 1u) << frames[k] << " frames";
    coverage[k] = marker_coverage(r.markers[0].detection, r.image);
    const nlohmann::json j = result_to_json(r, InputInfo{});
    EXPECT_NEAR(j["markers"][0]["coverage"].get<double>(), coverage[k], 1e-3);
  }
  std::printf("Mid-40 marker coverage: %.3f after 10 frames, %.3f after 60\n", coverage[0],
              coverage[1]);
  // Measured 0.60 and 1.00 (the marker sits at the dense centre of the rosette).
  EXPECT_GT(coverage[0], 0.4);
  EXPECT_LT(coverage[0], 0.8);
  EXPECT_GT(coverage[1], 0.95);
  EXPECT_LE(coverage[1], 1.0);

  eval::CaseSpec spec = eval::tag_wall_spec("os1-128", 3, 1.0);
  // The photon count the OS1 presets normalise (their default).
  spec.physics.intensity_model = sim::SimOptions::IntensityModel::kRaw;
  const eval::SimulatedCase c = eval::simulate_case(spec, 1);
  Pipeline pipeline(eval::pipeline_options_for(c, LiftMethod::kPlane));
  const FrameResult& r = pipeline.process(c.scan.cloud);
  ASSERT_EQ(r.markers.size(), 1u);
  const double ring_coverage = marker_coverage(r.markers[0].detection, r.image);
  std::printf("OS1-128 marker coverage: %.3f\n", ring_coverage);
  EXPECT_GT(ring_coverage, 0.97);
}

}  // namespace
}  // namespace iilfm
