// Sensor presets: figures from the data sheets and the name lookup.
#include "iilfm/sim/sensor_models.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "iilfm/error.hpp"
#include "iilfm/sim/scenes.hpp"
#include "iilfm/sim/simulate.hpp"

namespace iilfm::sim {
namespace {

TEST(SensorModels, Mid40IsARosetteWithTheDataSheetFigures) {
  const SensorModel s = mid40();
  EXPECT_EQ(s.name, "mid40");
  EXPECT_EQ(s.pattern, ScanPattern::kRosette);
  EXPECT_DOUBLE_EQ(s.fov_deg, 38.4);
  EXPECT_DOUBLE_EQ(s.points_per_second, 100000);
  EXPECT_DOUBLE_EQ(s.frame_rate_hz, 10);
  EXPECT_DOUBLE_EQ(s.range_sigma_m, 0.02);
  EXPECT_DOUBLE_EQ(s.min_range_m, 1.0);
  EXPECT_EQ(points_per_frame(s), 10000);
}

TEST(SensorModels, Vlp16Has16EvenRingsAnd1800Columns) {
  const SensorModel s = vlp16();
  ASSERT_EQ(s.ring_elevations_deg.size(), 16u);
  for (int r = 0; r < 16; ++r) EXPECT_DOUBLE_EQ(s.ring_elevations_deg[r], -15.0 + 2 * r);
  EXPECT_DOUBLE_EQ(s.azimuth_step_deg, 0.2);
  EXPECT_DOUBLE_EQ(s.range_sigma_m, 0.03);
  EXPECT_EQ(points_per_frame(s), 16 * 1800);
}

TEST(SensorModels, UltraPuckHas32RisingRingsFromMinus25To15) {
  const SensorModel s = ultra_puck();
  ASSERT_EQ(s.ring_elevations_deg.size(), 32u);
  EXPECT_DOUBLE_EQ(s.ring_elevations_deg.front(), -25);
  EXPECT_DOUBLE_EQ(s.ring_elevations_deg[20], 0);
  EXPECT_DOUBLE_EQ(s.ring_elevations_deg.back(), 15);
  for (std::size_t r = 1; r < 32; ++r) {
    EXPECT_GT(s.ring_elevations_deg[r], s.ring_elevations_deg[r - 1]) << "ring " << r;
  }
  EXPECT_EQ(points_per_frame(s), 32 * 1800);
  // The VLP-32C is the same laser layout under its own name.
  const SensorModel vlp32 = sensor_model("vlp32c");
  EXPECT_EQ(vlp32.name, "vlp32c");
  EXPECT_EQ(vlp32.ring_elevations_deg, s.ring_elevations_deg);
  EXPECT_EQ(vlp32.ring_azimuth_offsets_deg, s.ring_azimuth_offsets_deg);
}

TEST(SensorModels, Vlp16HiResHas16RingsOf1Point33DegreesInPlusMinus10) {
  const SensorModel s = vlp16_hires();
  ASSERT_EQ(s.ring_elevations_deg.size(), 16u);
  EXPECT_DOUBLE_EQ(s.ring_elevations_deg.front(), -10);
  EXPECT_DOUBLE_EQ(s.ring_elevations_deg.back(), 10);
  EXPECT_NEAR(s.ring_elevations_deg[1] - s.ring_elevations_deg[0], 1.333, 0.001);
  EXPECT_EQ(points_per_frame(s), 16 * 1800);
}

TEST(SensorModels, OusterOs1HasUniformRingsOver45DegreesAndItsColumns) {
  const SensorModel s64 = os1_64(), s128 = os1_128();
  ASSERT_EQ(s64.ring_elevations_deg.size(), 64u);
  ASSERT_EQ(s128.ring_elevations_deg.size(), 128u);
  EXPECT_DOUBLE_EQ(s64.ring_elevations_deg.front(), -22.5);
  EXPECT_DOUBLE_EQ(s64.ring_elevations_deg.back(), 22.5);
  EXPECT_NEAR(s128.ring_elevations_deg[1] - s128.ring_elevations_deg[0], 45.0 / 127, 1e-9);
  EXPECT_EQ(points_per_frame(s64), 64 * 1024);
  EXPECT_EQ(points_per_frame(s128), 128 * 2048);
}

TEST(SensorModels, VelodyneHdlModelsSpanTheirManualsFieldsInWholeColumns) {
  const SensorModel s32 = hdl32e(), s64 = hdl64e();
  ASSERT_EQ(s32.ring_elevations_deg.size(), 32u);
  ASSERT_EQ(s64.ring_elevations_deg.size(), 64u);
  EXPECT_DOUBLE_EQ(s32.ring_elevations_deg.front(), -30.67);
  EXPECT_DOUBLE_EQ(s32.ring_elevations_deg.back(), 10.67);
  EXPECT_NEAR(s32.ring_elevations_deg[1] - s32.ring_elevations_deg[0], 1.3335, 1e-4);
  EXPECT_DOUBLE_EQ(s64.ring_elevations_deg.front(), -24.9);
  EXPECT_DOUBLE_EQ(s64.ring_elevations_deg.back(), 2);
  EXPECT_EQ(points_per_frame(s32), 32 * 2250);
  EXPECT_EQ(points_per_frame(s64), 64 * 2118);
  // Whole columns: the sweep closes on itself without overlapping.
  EXPECT_NEAR(2118 * s64.azimuth_step_deg, 360, 1e-9);
}

TEST(SensorModels, OusterOs0AndOs2SpreadTheirRingsOver90And22Point5Degrees) {
  const SensorModel s0 = os0_128(), s2 = os2_128();
  ASSERT_EQ(s0.ring_elevations_deg.size(), 128u);
  ASSERT_EQ(s2.ring_elevations_deg.size(), 128u);
  EXPECT_DOUBLE_EQ(s0.ring_elevations_deg.front(), -45);
  EXPECT_DOUBLE_EQ(s0.ring_elevations_deg.back(), 45);
  EXPECT_DOUBLE_EQ(s2.ring_elevations_deg.front(), -11.25);
  EXPECT_DOUBLE_EQ(s2.ring_elevations_deg.back(), 11.25);
  EXPECT_EQ(points_per_frame(s0), 128 * 1024);
  EXPECT_EQ(points_per_frame(s2), 128 * 1024);
  EXPECT_TRUE(s0.raw_intensity);
  EXPECT_TRUE(s2.raw_intensity);
  // The same ring pitch in beam widths as the OS1.
  EXPECT_GT(s0.divergence_v_deg, os1_128().divergence_v_deg);
  EXPECT_LT(s2.divergence_v_deg, os1_128().divergence_v_deg);
}

TEST(SensorModels, HesaiXt32HasRingsOneDegreeApartAnd2000Columns) {
  const SensorModel s = xt32();
  ASSERT_EQ(s.ring_elevations_deg.size(), 32u);
  for (int r = 0; r < 32; ++r) EXPECT_NEAR(s.ring_elevations_deg[r], -16.0 + r, 1e-12);
  EXPECT_EQ(points_per_frame(s), 32 * 2000);
}

// How many steps between neighbouring rings lie within `tolerance` of `spacing`; every step
// must rise.
int rising_steps_near(const std::vector<double>& rings, double spacing, double tolerance) {
  int near = 0;
  for (std::size_t r = 1; r < rings.size(); ++r) {
    EXPECT_GT(rings[r], rings[r - 1]) << "ring " << r;
    near += std::abs(rings[r] - rings[r - 1] - spacing) < tolerance;
  }
  return near;
}

TEST(SensorModels, HesaiPandar40PPacksAThirdOfADegreeAroundTheHorizon) {
  const SensorModel s = pandar40p();
  const std::vector<double>& rings = s.ring_elevations_deg;
  ASSERT_EQ(rings.size(), 40u);
  EXPECT_DOUBLE_EQ(rings.front(), -25);
  EXPECT_DOUBLE_EQ(rings.back(), 15);
  EXPECT_EQ(rising_steps_near(rings, 1.0 / 3, 1e-9), 24);  // -6 to +2 deg
  EXPECT_EQ(points_per_frame(s), 40 * 1800);
  EXPECT_EQ(s.intensity_curve, xt32().intensity_curve);
}

// The QT64's rings are 1.45 deg apart at the horizon and widen to 2.34 deg at the field's edges;
// its channels point 5-9 deg either side of their column, in four blocks of 16.
TEST(SensorModels, HesaiQt64WidensItsRingsAwayFromTheHorizon) {
  const SensorModel s = qt64();
  const std::vector<double>& rings = s.ring_elevations_deg;
  ASSERT_EQ(rings.size(), 64u);
  EXPECT_NEAR(rings.front(), -52.1, 0.05);
  EXPECT_NEAR(rings.back(), 52.1, 0.05);
  for (std::size_t r = 2; r < 32; ++r)  // the spacing shrinks from the bottom edge to the horizon
    ASSERT_LT(rings[r] - rings[r - 1], rings[r - 1] - rings[r - 2]) << r;
  EXPECT_NEAR(rings[32] - rings[31], 1.45, 0.01);
  EXPECT_NEAR(rings[1] - rings[0], 2.34, 0.01);
  ASSERT_EQ(s.ring_azimuth_offsets_deg.size(), 64u);
  for (std::size_t r = 0; r < 64; ++r) {
    const double offset = s.ring_azimuth_offsets_deg[r];
    EXPECT_GT(std::abs(offset), 4.8) << r;
    EXPECT_LT(std::abs(offset), 9) << r;
    EXPECT_EQ(offset > 0, (r / 16) % 2 == 0) << r;
  }
  EXPECT_EQ(points_per_frame(s), 64 * 600);
  EXPECT_EQ(s.intensity_curve, xt32().intensity_curve);
}

// The RS-LiDAR-32 packs 20 of its rings a third of a degree apart (to within 0.08 deg, one unit's
// calibration) between -4.7 and +1.7 deg; its channels point 2-9 deg either side of their column.
TEST(SensorModels, RoboSenseRs32PacksAThirdOfADegreeAroundTheHorizon) {
  const SensorModel s = rs32();
  const std::vector<double>& rings = s.ring_elevations_deg;
  ASSERT_EQ(rings.size(), 32u);
  EXPECT_NEAR(rings.front(), -25, 0.05);
  EXPECT_NEAR(rings.back(), 15, 0.05);
  EXPECT_EQ(rising_steps_near(rings, 1.0 / 3, 0.08), 19);  // -4.667 to +1.667 deg
  ASSERT_EQ(s.ring_azimuth_offsets_deg.size(), 32u);
  for (const double offset : s.ring_azimuth_offsets_deg) {
    EXPECT_GT(std::abs(offset), 2);
    EXPECT_LT(std::abs(offset), 9);
  }
  EXPECT_EQ(points_per_frame(s), 32 * 1800);
}

// Hesai's scale as on the real Pandar64 frames: print black 60-85, white 110-145, the surfaces
// near the sensor above 100, so the preset's threshold of 100 splits ink from paper and wall; the
// calibrated reflectivity of the other models (black 10, wall 60, white 120) would not.
TEST(SensorModels, HesaiXt32ReportsPrintOnHesaisOffsetScale) {
  const SensorModel s = xt32();
  EXPECT_DOUBLE_EQ(reported_intensity(s, 10), 72);
  EXPECT_DOUBLE_EQ(reported_intensity(s, 35), 93.5);  // between anchors: linear
  EXPECT_DOUBLE_EQ(reported_intensity(s, 60), 115);
  EXPECT_DOUBLE_EQ(reported_intensity(s, 120), 128);
  EXPECT_NEAR(reported_intensity(s, 0), 72 - 10 * 43.0 / 50, 1e-12);  // the first slope beyond
  EXPECT_DOUBLE_EQ(reported_intensity(s, 400), 255);                  // clamped
  EXPECT_DOUBLE_EQ(reported_intensity(vlp16(), 37.5), 37.5);          // no curve: as is

  SceneParams params;
  params.distance_m = 2;
  const SceneSetup setup = named_scene("tag-wall", params);
  SimOptions options;
  options.T_world_lidar = setup.T_world_lidar;
  options.intensity_sigma = 0;
  for (auto model :
       {SimOptions::IntensityModel::kSensor, SimOptions::IntensityModel::kReflectivity}) {
    options.intensity_model = model;
    const SimResult r = simulate(setup.scene, s, options);
    ASSERT_GT(r.cloud.size(), 1000u);
    const auto [lo, hi] = std::minmax_element(r.cloud.intensity.begin(), r.cloud.intensity.end());
    const bool own = model == SimOptions::IntensityModel::kSensor;
    EXPECT_NEAR(*lo, own ? 72 : 10, 0.01);    // black print
    EXPECT_NEAR(*hi, own ? 128 : 120, 0.01);  // white paper
  }
}

TEST(SensorModels, DivergenceFromTheDataSheets) {
  EXPECT_DOUBLE_EQ(mid40().divergence_v_deg, 0.28);
  EXPECT_DOUBLE_EQ(mid40().divergence_h_deg, 0.03);
  EXPECT_DOUBLE_EQ(vlp16().divergence_h_deg, 0.17);
  EXPECT_DOUBLE_EQ(ultra_puck().divergence_v_deg, 0.17);
  for (const std::string& name : sensor_model_names()) {
    EXPECT_DOUBLE_EQ(sensor_model(name).intensity_sigma, 4) << name;
  }
}

TEST(SensorModels, LookupByNameAndUnknownNamesListTheKnownOnes) {
  for (const std::string& name : sensor_model_names()) EXPECT_EQ(sensor_model(name).name, name);
  try {
    sensor_model("hdl64");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("hdl64"), std::string::npos) << message;
    EXPECT_NE(message.find("mid40, vlp16, ultrapuck"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace iilfm::sim
