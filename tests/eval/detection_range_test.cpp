// The detection-range study on the sensor where ring rows matter most: the ULTRA Puck's 32
// non-uniform rings leave the paper's uniform rows mostly empty around a marker level with it.
#include "iilfm/eval/detection_range.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

namespace iilfm::eval {
namespace {

// The paper settings' and iilfm's walks over one distance, every one of `seeds` seeds required.
std::vector<RangeResult> paper_and_iilfm_at(const std::string& sensor, double size_m,
                                            double distance_m, int seeds) {
  RangeQuery query;
  query.sensor = sensor;
  query.marker_size_m = size_m;
  query.distances = {distance_m};
  query.seeds = query.required = seeds;
  return detection_range(query, {RangeSettings::kPaper, RangeSettings::kIilfm});
}

TEST(DetectionRange, RingRowsFindAMarkerThePaperSettingsMissOnTheUltraPuck) {
  // Five seeds: the footprint's 25 sub-rays a beam are slow under ASan.
  const std::vector<RangeResult> r = paper_and_iilfm_at("ultrapuck", 0.4, 1.0, 5);
  ASSERT_EQ(r.size(), 2u);
  ASSERT_EQ(r[0].found.size(), 1u);
  ASSERT_EQ(r[1].found.size(), 1u);
  // Measured with 10 seeds: paper settings 0 of 10, iilfm 10 of 10, no false positive.
  EXPECT_LE(r[0].found[0].second, 1);
  EXPECT_EQ(r[1].found[0].second, 5);
  EXPECT_EQ(r[1].max_distance_m, 1.0);
  EXPECT_EQ(r[0].max_distance_m, 0.0);
  EXPECT_EQ(r[0].false_positives + r[1].false_positives, 0);
  const std::string table = range_table_markdown(r);
  EXPECT_NE(table.find("| ultrapuck | 0.4 m | - | 1.0-1.0 m | new | 0 |"), std::string::npos)
      << table;
}

// On the VLP-16 the limit is geometric: a tag36h11 needs about a ring per cell row, and both
// settings see the same rings. The walk must still find the 40 cm tag up to 2.5 m, where 4.6
// rings cross its 8 cell rows, and not reliably at 3 m, where 3.8 do and most placements leave
// too few cells read.
TEST(DetectionRange, Vlp16FortyCentimetreTagIsRingLimited) {
  RangeQuery query;
  query.sensor = "vlp16";
  query.marker_size_m = 0.4;
  query.distances = {1.0, 2.0, 2.5, 3.0};
  query.footprint = false;
  const std::vector<RangeResult> r = detection_range(query, {RangeSettings::kIilfm});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].max_distance_m, 2.5);
  ASSERT_EQ(r[0].found.size(), 4u);
  // Measured at 2 m: 10 of 10 since a known id needs three bits to every other code (session 26),
  // 8 in session 25, 2 before the map's id was read from fewer ring samples. At 2.5 m: 10 of 10
  // since the ring candidates' sides are also read moved half a pixel (session 32), 7 before. At
  // 3 m: 6 of 10.
  EXPECT_LT(r[0].found[3].second, query.required);
  EXPECT_EQ(r[0].false_positives, 0);
}

// An OS2-128 at 1024 columns has columns twice as coarse as its rings: a 17 cm tag36h11 at 4 m
// spans 7 columns for its 8 cells. AprilTag reads it to 3.5 m (8 columns) and the paper settings
// to 2.5 m; the ring candidates read it at 4 m, their placings moving its left and right sides.
TEST(DetectionRange, Os2128SeventeenCentimetreTagAtFourMetres) {
  RangeQuery query;
  query.sensor = "os2-128";
  query.marker_size_m = 0.172;
  query.distances = {4.0};
#ifndef NDEBUG
  // The beam footprint's 25 sub-rays a beam over 1.3 M beams take 25 s a seed under ASan.
  query.seeds = 4;
  query.required = 3;
#endif
  const std::vector<RangeResult> r = detection_range(query, {RangeSettings::kIilfm});
  ASSERT_EQ(r.size(), 1u);
  ASSERT_EQ(r[0].found.size(), 1u);
  // Measured: 10 of 10 (0 of 10 before the placings moved along the coarse columns).
  EXPECT_GE(r[0].found[0].second, query.required);
  EXPECT_EQ(r[0].false_positives, 0);
}

// A PandarQT64's rings are 1.45 deg apart at the horizon and up to 2.3 deg at its field's edges.
// A 1 m tag 2 m away spans 28 deg, out to where the rings are 1.6 deg apart: the paper settings'
// uniform rows at the finest spacing leave empty rows across it, ring rows do not. A 40 cm tag at
// 3 m spans 5 rings for its 8 cell rows, where the paper settings' AprilTag stops.
TEST(DetectionRange, Qt64RingRowsReadMarkersThePaperSettingsMiss) {
  for (const auto& [size_m, distance_m] : {std::pair{1.0, 2.0}, std::pair{0.4, 3.0}}) {
    SCOPED_TRACE(size_m);
#ifdef NDEBUG
    const int seeds = 10;
#else
    const int seeds = 5;  // the footprint's sub-rays are slow under the sanitizers
#endif
    const std::vector<RangeResult> r = paper_and_iilfm_at("qt64", size_m, distance_m, seeds);
    ASSERT_EQ(r.size(), 2u);
    ASSERT_EQ(r[0].found.size(), 1u);
    ASSERT_EQ(r[1].found.size(), 1u);
    // Measured with 10 seeds: paper settings 0 of 10 for both, iilfm 10 of 10.
    EXPECT_LE(r[0].found[0].second, 1);
    EXPECT_EQ(r[1].found[0].second, seeds);
    EXPECT_EQ(r[0].false_positives + r[1].false_positives, 0);
  }
}

// A Mid-360's 40 integrated frames leave a fifth of its 0.2 deg pixels without a point: without
// hole filling each is a black speck on the paper, and a 17 cm tag at 2.5 m (8 pixels a cell)
// is lost to the paper settings where iilfm reads it.
TEST(DetectionRange, Mid360HoleFillingReadsTheTagThePaperSettingsLoseToSpecks) {
#ifdef NDEBUG
  const int seeds = 10;
#else
  const int seeds = 5;    // the footprint's sub-rays are slow under the sanitizers
#endif
  const std::vector<RangeResult> r = paper_and_iilfm_at("mid360", 0.172, 2.5, seeds);
  ASSERT_EQ(r.size(), 2u);
  ASSERT_EQ(r[0].found.size(), 1u);
  ASSERT_EQ(r[1].found.size(), 1u);
  // Measured with 10 seeds: paper settings 2 of 10, iilfm 10 of 10.
  EXPECT_LE(r[0].found[0].second, seeds / 2);
  EXPECT_EQ(r[1].found[0].second, seeds);
  EXPECT_EQ(r[0].false_positives + r[1].false_positives, 0);
}

// The HDL-32E's field runs from -30.67 to +10.67 deg: level with it, a 1 m tag 2 m away reaches
// 14 deg up and is clipped. The walk tilts the LiDAR up so the marker sits mid-field.
TEST(DetectionRange, AimsTheMiddleOfADownLookingFieldAtTheMarker) {
  EXPECT_EQ(aim_pitch_deg("hdl32e"), -10.0);
  EXPECT_EQ(aim_pitch_deg("hdl64e"), -11.0);
  EXPECT_EQ(aim_pitch_deg("vlp16"), 0.0);
  EXPECT_EQ(aim_pitch_deg("ultrapuck"), 0.0);  // its rings are packed around the horizon
  EXPECT_EQ(aim_pitch_deg("mid40"), 0.0);
  EXPECT_EQ(aim_pitch_deg("mid360"), 23.0);  // its -7..+52 deg band looks up: tilted down

  CaseSpec spec = tag_wall_spec("hdl32e", 2.0, 1.0);
  for (double pitch : {0.0, aim_pitch_deg("hdl32e")}) {
    spec.lidar_rpy_deg = Vec3(0, pitch, 0);
    const SimulatedCase c = simulate_case(spec, 1);
    ASSERT_EQ(c.scan.truth.markers.size(), 1u);
    const sim::MarkerTruth& m = c.scan.truth.markers[0];
    const Vec3 centre = m.T_lidar_marker.translation();
    const double elevation_deg = std::atan2(centre.z(), centre.head<2>().norm()) * 180 / M_PI;
    if (pitch == 0) {
      EXPECT_NEAR(elevation_deg, 0.0, 0.5);
      EXPECT_FALSE(m.visible);  // its top corners lie above the top ring
    } else {
      EXPECT_NEAR(elevation_deg, -10.0, 0.5);
      EXPECT_TRUE(m.visible);
    }
  }
}

}  // namespace
}  // namespace iilfm::eval
