// The optional physics: beam footprint (mixed returns at edges), dropouts on black print,
// invalid points, minimum range, per-sensor intensity noise; and that none of them changes the
// noise of the beams that still return.
#include <gtest/gtest.h>

#include <cmath>

#include "iilfm/error.hpp"
#include "iilfm/sim/sim.hpp"
#include "plain_wall.hpp"

namespace iilfm::sim {
namespace {

SimOptions paper_setup(int frames) {
  SimOptions o;
  o.T_world_lidar = named_scene("tag-wall").T_world_lidar;
  o.frames = frames;
  o.range_sigma_m = 0;
  o.intensity_sigma = 0;
  return o;
}

// Intensities of returns that land inside the outer black square of the tag-wall marker.
std::vector<float> marker_intensities(const SimResult& r) {
  std::vector<float> values;
  const std::array<Vec3, 4>& c = r.truth.markers.front().corners_lidar;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Vec3 p = r.cloud.point(i);
    if (p.y() < c[0].y() && p.y() > c[1].y() && p.z() < c[0].z() && p.z() > c[3].z()) {
      values.push_back(r.cloud.intensity[i]);
    }
  }
  return values;
}

TEST(Physics, FootprintTurnsEdgesGreyAndKeepsTheRestBlackOrWhite) {
  const Scene scene = named_scene("tag-wall").scene;
  SimOptions o = paper_setup(20);
  const std::vector<float> sharp = marker_intensities(simulate(scene, mid40(), o));
  o.footprint = true;
  const std::vector<float> blurred = marker_intensities(simulate(scene, mid40(), o));
  ASSERT_EQ(sharp.size(), blurred.size());  // same beams, same hits: only intensity changes
  int grey_sharp = 0, grey_blurred = 0;
  for (float v : sharp) grey_sharp += v > 10.5f && v < 119.5f;
  for (float v : blurred) grey_blurred += v > 10.5f && v < 119.5f;
  EXPECT_EQ(grey_sharp, 0);
  // 0.28 deg at 2 m is 9.8 mm tall, against 21.5 mm cells: a good share of the returns straddle
  // a horizontal black-white edge, hardly any a vertical one (0.03 deg wide).
  const double share = static_cast<double>(grey_blurred) / blurred.size();
  std::cout << "[ measured ] Mid-40 footprint at 2 m: " << 100 * share << " % grey returns\n";
  // Measured 13.5 %; about half the cell boundaries are black-white edges: 9.8 / 21.5 / 2.
  EXPECT_GT(share, 0.08);
  EXPECT_LT(share, 0.25);
}

TEST(Physics, FootprintSubRaysFollowTheDivergence) {
  const Scene scene = named_scene("tag-wall").scene;
  SimOptions o = paper_setup(1);
  o.footprint = true;
  o.footprint_samples = 0;
  EXPECT_THROW(simulate(scene, mid40(), o), InputError);
  // A uniform wall reads the same with and without the footprint (away from its edges).
  const Scene plain = testing::plain_wall(5, 20, 70);
  SimOptions p;
  p.range_sigma_m = p.intensity_sigma = 0;
  p.footprint = true;
  const SimResult r = simulate(plain, vlp16(), p);
  std::size_t inside = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    if (std::abs(r.cloud.y[i]) > 8) continue;  // sub-rays past the wall's edge add nothing
    EXPECT_FLOAT_EQ(r.cloud.intensity[i], 70);
    ++inside;
  }
  EXPECT_GT(inside, 1000u);
}

TEST(Physics, DarkDropoutLosesReturnsOnBlackPrintOnly) {
  const Scene scene = named_scene("tag-wall").scene;
  SimOptions o = paper_setup(20);
  const SimResult all = simulate(scene, mid40(), o);
  o.dark_dropout = 1;
  const SimResult dropped = simulate(scene, mid40(), o);
  for (float v : marker_intensities(dropped)) EXPECT_FLOAT_EQ(v, 120);  // no black left
  std::size_t black = 0;
  for (float v : all.cloud.intensity) black += v == 10;
  EXPECT_GT(black, 1000u);
  EXPECT_EQ(dropped.cloud.size(), all.cloud.size() - black);
  o.dark_dropout = 1.5;
  EXPECT_THROW(simulate(scene, mid40(), o), InputError);
}

TEST(Physics, HalfTheBlackReturnsSurviveAHalfDropout) {
  const Scene scene = named_scene("tag-wall").scene;
  SimOptions o = paper_setup(20);
  o.dark_dropout = 0.5;
  const SimResult r = simulate(scene, mid40(), o);
  o.dark_dropout = 0;
  const SimResult all = simulate(scene, mid40(), o);
  std::size_t black_all = 0, black_kept = 0;
  for (float v : all.cloud.intensity) black_all += v == 10;
  for (float v : r.cloud.intensity) black_kept += v == 10;
  EXPECT_NEAR(static_cast<double>(black_kept) / black_all, 0.5, 0.02);
}

TEST(Physics, InvalidPointsAreNaNOrZeroInTheirShare) {
  const Scene scene = named_scene("tag-wall").scene;
  SimOptions o = paper_setup(5);
  o.invalid_fraction = 0.1;
  const SimResult nan = simulate(scene, mid40(), o);
  std::size_t invalid = 0;
  for (std::size_t i = 0; i < nan.cloud.size(); ++i) invalid += std::isnan(nan.cloud.x[i]);
  EXPECT_NEAR(static_cast<double>(invalid) / nan.cloud.size(), 0.1, 0.01);
  o.invalid_as = SimOptions::Invalid::kZero;
  const SimResult zero = simulate(scene, mid40(), o);
  ASSERT_EQ(zero.cloud.size(), nan.cloud.size());
  std::size_t zeros = 0;
  for (std::size_t i = 0; i < zero.cloud.size(); ++i) {
    zeros += zero.cloud.x[i] == 0 && zero.cloud.y[i] == 0 && zero.cloud.z[i] == 0;
  }
  EXPECT_EQ(zeros, invalid);
}

TEST(Physics, OptionalEffectsLeaveTheNoiseOfKeptBeamsAlone) {
  const Scene scene = named_scene("tag-wall").scene;
  SimOptions o = paper_setup(3);
  o.range_sigma_m = 0.02;
  o.intensity_sigma = 4;
  const SimResult plain = simulate(scene, mid40(), o);
  o.invalid_fraction = 0.2;
  o.dark_dropout = 0.3;
  const SimResult thinned = simulate(scene, mid40(), o);
  // Every valid point of the thinned scan is one of the plain scan's, in the same order.
  std::size_t j = 0, matched = 0;
  for (std::size_t i = 0; i < thinned.cloud.size(); ++i) {
    if (std::isnan(thinned.cloud.x[i])) continue;
    while (j < plain.cloud.size() && plain.cloud.time[j] != thinned.cloud.time[i]) ++j;
    ASSERT_LT(j, plain.cloud.size());
    EXPECT_EQ(plain.cloud.x[j], thinned.cloud.x[i]);
    EXPECT_EQ(plain.cloud.intensity[j], thinned.cloud.intensity[i]);
    ++matched;
  }
  EXPECT_GT(matched, plain.cloud.size() / 2);
}

TEST(Physics, MinimumRangeOverrideDropsCloseReturns) {
  const Scene scene = named_scene("tag-wall").scene;
  SimOptions o = paper_setup(2);
  // The wall is 2 m ahead at the centre and 2.12 m at the cone's rim; the floor is closer.
  o.min_range_m = 2.05;
  const SimResult r = simulate(scene, mid40(), o);
  ASSERT_GT(r.cloud.size(), 1000u);
  for (std::size_t i = 0; i < r.cloud.size(); ++i) EXPECT_GE(r.cloud.point(i).norm(), 2.05 - 1e-5);
  EXPECT_FALSE(r.truth.markers.front().visible);  // the marker is inside the blind zone now
}

TEST(Physics, IntensityNoiseDefaultsToTheSensors) {
  const Scene plain = testing::plain_wall(5, 20, 70);
  SensorModel sensor = vlp16();
  sensor.intensity_sigma = 9;
  SimOptions o;
  o.range_sigma_m = 0;
  const SimResult r = simulate(plain, sensor, o);
  double sum = 0, sum2 = 0;
  for (float v : r.cloud.intensity) {
    sum += v;
    sum2 += v * v;
  }
  const double n = static_cast<double>(r.cloud.size());
  const double sigma = std::sqrt(sum2 / n - (sum / n) * (sum / n));
  EXPECT_NEAR(sigma, 9, 0.2);
}

}  // namespace
}  // namespace iilfm::sim
