// The vectorised passes of the robust plane fit against plain loops over the same points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "../../src/plane_fit_passes.hpp"

namespace iilfm::detail {
namespace {

// 1003 points (not a multiple of the 4 lanes) scattered about a tilted plane 3 m away.
FitPoints some_points(std::size_t n = 1003) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> across(-0.5, 0.5);
  std::normal_distribution<double> noise(0, 0.004);
  FitPoints p;
  for (std::size_t k = 0; k < n; ++k) {
    const double a = across(rng), b = across(rng);
    p.x.push_back(3.0 + 0.2 * a + noise(rng));
    p.y.push_back(a);
    p.z.push_back(b);
  }
  return p;
}

TEST(PlaneFitPasses, CoordinateSumsAreThePlainSums) {
  const FitPoints p = some_points();
  const Vec3 ref(3, 0.1, -0.2);
  const CoordinateSums s = coordinate_sums(p, ref);
  double x = 0, yz = 0, zz = 0, xx = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double a = p.x[k] - ref.x(), b = p.y[k] - ref.y(), c = p.z[k] - ref.z();
    x += a;
    xx += a * a;
    yz += b * c;
    zz += c * c;
  }
  EXPECT_EQ(s.n, 1003.0);
  EXPECT_NEAR(s.x, x, 1e-10);
  EXPECT_NEAR(s.xx, xx, 1e-10);
  EXPECT_NEAR(s.yz, yz, 1e-10);
  EXPECT_NEAR(s.zz, zz, 1e-10);
  EXPECT_GT(zz, 50);  // the sums are not trivially zero
}

TEST(PlaneFitPasses, ResidualsAndKeepWithinKeepTheBandInOrder) {
  const FitPoints p = some_points();
  const Vec3 normal = Vec3(1, -0.2, 0).normalized();
  const double d = normal.x() * 3.0;
  std::vector<double> residual(p.size());
  plane_residuals(p, normal, d, residual.data());
  // A band that drops a third of the points, one that drops a few (whole blocks kept, others
  // not), and one that keeps all.
  for (const double band : {0.004, 0.0095, 1.0}) {
    FitPoints kept;
    const std::size_t n = keep_within(p, residual.data(), band, kept);
    std::vector<std::size_t> expected;
    for (std::size_t k = 0; k < p.size(); ++k) {
      const double r =
          std::abs(normal.x() * p.x[k] + normal.y() * p.y[k] + normal.z() * p.z[k] - d);
      EXPECT_NEAR(residual[k], r, 1e-12);
      if (r <= band) expected.push_back(k);
    }
    ASSERT_EQ(n, expected.size()) << band;
    ASSERT_EQ(kept.size(), n);
    for (std::size_t k = 0; k < n; ++k) {
      ASSERT_EQ(kept.x[k], p.x[expected[k]]) << band;
      ASSERT_EQ(kept.y[k], p.y[expected[k]]) << band;
      ASSERT_EQ(kept.z[k], p.z[expected[k]]) << band;
    }
    if (band == 0.004) {
      EXPECT_GT(n, 500u);  // about 68 % of a 1-sigma band
      EXPECT_LT(n, p.size());
    } else if (band < 1) {
      EXPECT_GT(n, p.size() - 30);  // a few dropped, so some blocks are kept whole
      EXPECT_LT(n, p.size() - 2);
    } else {
      EXPECT_EQ(n, p.size());
    }
  }
}

TEST(PlaneFitPasses, CoordinateSumsOfARangeAreThoseOfItsPoints) {
  const FitPoints p = some_points();
  const Vec3 ref(3, 0, 0);
  for (const auto& [begin, end] :
       {std::pair<std::size_t, std::size_t>{0, 1003}, {5, 6}, {7, 500}, {998, 1003}, {400, 400}}) {
    FitPoints part;
    for (std::size_t k = begin; k < end; ++k) {
      part.x.push_back(p.x[k]);
      part.y.push_back(p.y[k]);
      part.z.push_back(p.z[k]);
    }
    const CoordinateSums a = coordinate_sums(p, ref, begin, end), b = coordinate_sums(part, ref);
    EXPECT_EQ(a.n, static_cast<double>(end - begin));
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.yz, b.yz);
    EXPECT_EQ(a.zz, b.zz);
  }
}

TEST(PlaneFitPasses, LabelledPointsAreKeptAndAppendedInOrder) {
  const FitPoints p = some_points();
  std::vector<std::uint8_t> label(p.size());
  std::vector<double> value(p.size());
  std::mt19937 rng(3);
  for (std::size_t k = 0; k < p.size(); ++k) {
    label[k] = static_cast<std::uint8_t>(rng() % 4);  // 0 to 3
    value[k] = static_cast<double>(rng() % 100);
  }
  FitPoints kept;
  keep_labelled(p, label.data(), 2, 3, kept);
  FitPoints appended = kept;
  append_labelled_within(p, label.data(), 1, 2, value.data(), 49.0, appended);
  std::vector<std::size_t> first, second;
  for (std::size_t k = 0; k < p.size(); ++k) {
    if (label[k] >= 2) first.push_back(k);
    if (label[k] >= 1 && label[k] <= 2 && value[k] <= 49) second.push_back(k);
  }
  ASSERT_EQ(kept.size(), first.size());
  ASSERT_EQ(appended.size(), first.size() + second.size());
  EXPECT_GT(second.size(), 150u);  // about a quarter of the points
  for (std::size_t k = 0; k < appended.size(); ++k) {
    const std::size_t from = k < first.size() ? first[k] : second[k - first.size()];
    ASSERT_EQ(appended.x[k], p.x[from]) << k;
    ASSERT_EQ(appended.y[k], p.y[from]) << k;
    ASSERT_EQ(appended.z[k], p.z[from]) << k;
  }
}

TEST(PlaneFitPasses, SpreadSumsGiveTheInPlaneExtent) {
  const FitPoints p = some_points();
  const Vec3 normal(1, 0, 0), centre(3, 0, 0), axis1(0, 1, 0), axis2(0, 0, 1);
  const SpreadSums s = spread_sums(p, normal, 3.0, centre, axis1, axis2);
  double lo = 1e9, hi = -1e9, sum_sq = 0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    lo = std::min<double>(lo, p.z[k]);
    hi = std::max<double>(hi, p.y[k]);
    const double off = static_cast<double>(p.x[k]) - 3;
    sum_sq += off * off;
  }
  EXPECT_EQ(s.min2, lo);
  EXPECT_EQ(s.max1, hi);
  EXPECT_NEAR(s.sum_sq, sum_sq, 1e-12);
}

TEST(PlaneFitPasses, GridPatchesClampOutsidersAndNaNToTheEdge) {
  FitPoints p = some_points(5);
  // In-plane coordinates (y, z): inside, beyond both far edges, before both near edges, far in y
  // and near in z, NaN.
  p.y = {0.1, 9.0, -9.0, 0.4, std::numeric_limits<double>::quiet_NaN()};
  p.z = {-0.1, 9.0, -9.0, -0.4, 0.0};
  const double extent[4] = {-0.5, 0.5, -0.5, 0.5};
  std::vector<std::int32_t> patch(p.size());
  grid_patches(p, Vec3(3, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), extent, 4, patch.data());
  EXPECT_EQ(patch[0], 2 * 4 + 1);  // y 0.1 -> column 2 of 4, z -0.1 -> 1
  EXPECT_EQ(patch[1], 15);
  EXPECT_EQ(patch[2], 0);
  EXPECT_EQ(patch[3], 3 * 4 + 0);
  EXPECT_EQ(patch[4], 0);  // a NaN coordinate makes both dot products NaN: the first patch
}

TEST(PlaneFitPasses, RayPointsAreThePlainProducts) {
  // 37 rays (not a multiple of the lanes) across 30 deg of azimuth at 12 deg of elevation.
  const double elevation = 12 * M_PI / 180, cos_el = std::cos(elevation),
               sin_el = std::sin(elevation);
  std::vector<double> cos_az, sin_az;
  std::vector<float> range;
  for (int k = 0; k < 37; ++k) {
    const double azimuth = (-15 + 30.0 * k / 36) * M_PI / 180;
    cos_az.push_back(std::cos(azimuth));
    sin_az.push_back(std::sin(azimuth));
    range.push_back(static_cast<float>(2.5 + 0.37 * k));
  }
  std::vector<float> x(37), y(37), z(37);
  ray_points(cos_el, sin_el, cos_az.data(), sin_az.data(), range.data(), 37, x.data(), y.data(),
             z.data());
  for (int k = 0; k < 37; ++k) {
    const double along = range[k];
    EXPECT_EQ(x[k], static_cast<float>(cos_el * cos_az[k] * along)) << k;
    EXPECT_EQ(y[k], static_cast<float>(cos_el * sin_az[k] * along)) << k;
    EXPECT_EQ(z[k], static_cast<float>(sin_el * along)) << k;
    // And they lie on their rays, at their range.
    EXPECT_NEAR(std::hypot(x[k], y[k], z[k]), along, 1e-5 * along) << k;
    EXPECT_NEAR(std::atan2(z[k], std::hypot(x[k], y[k])), elevation, 1e-6) << k;
  }
}

TEST(PlaneFitPasses, ValueOfRankIsWhatNthElementSelects) {
  std::mt19937 rng(3);
  std::exponential_distribution<double> residual(200.0);  // a residual-like long tail
  for (const std::size_t n : {1u, 7u, 1024u, 1025u, 10000u, 10003u, 16384u}) {
    for (const bool outlier : {false, true}) {
      std::vector<double> v(n);
      for (double& x : v) x = residual(rng);
      // Ties: a quarter of the values repeat one value; an outlier stretches the range (and puts
      // the rest in one bin).
      for (std::size_t k = 0; k < n / 4; ++k) v[4 * k] = v[0];
      if (n > 2 && outlier) v[1] = 50.0;
      // The extremes, the middle, and the ranks of the last values (counted apart from the rest
      // when n is not a multiple of four).
      std::vector<double> sorted = v;
      std::sort(sorted.begin(), sorted.end());
      std::vector<std::size_t> ranks = {0, n / 2, n - 1};
      for (std::size_t k = n - std::min<std::size_t>(n, 3); k < n; ++k)
        ranks.push_back(static_cast<std::size_t>(
            std::lower_bound(sorted.begin(), sorted.end(), v[k]) - sorted.begin()));
      for (const std::size_t rank : ranks)
        EXPECT_EQ(value_of_rank(v.data(), n, rank), sorted[rank]) << "n " << n << " rank " << rank;
    }
  }
  const std::vector<double> same(5000, 0.25);  // no range to split
  EXPECT_EQ(value_of_rank(same.data(), same.size(), 2500), 0.25);
}

}  // namespace
}  // namespace iilfm::detail
