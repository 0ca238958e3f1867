// Ring rows: ring structure from the ring field and from elevations, the piecewise-linear row
// geometry and its exact inverse, ring-aware projection, and the square-pixel mapping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <random>

#include "iilfm/projection.hpp"
#include "iilfm/ring_structure.hpp"
#include "iilfm/square_pixels.hpp"

namespace iilfm {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A VLP-32C-like non-uniform layout: dense 0.33 deg near the horizon, sparse above and below.
std::vector<double> nonuniform_rings_deg() {
  std::vector<double> rings;
  for (double e = -25; e < -8.5; e += 3.4) rings.push_back(e);
  for (double e = -8; e < 2.5; e += 0.333) rings.push_back(e);
  for (double e = 3; e <= 15; e += 2.4) rings.push_back(e);
  return rings;
}

// One point per ring and column at range 5-15 m, ring field as the driver writes it (ring 0 the
// lowest), in a shuffled order.
PointCloud spinning_cloud(const std::vector<double>& rings_deg, double step_deg, bool with_ring) {
  PointCloud cloud;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> range(5, 15);
  for (std::size_t ring = 0; ring < rings_deg.size(); ++ring) {
    for (double az = -180 + step_deg / 2; az < 180; az += step_deg) {
      const double e = rings_deg[ring] * kDeg, a = az * kDeg, r = range(rng);
      cloud.push_back(static_cast<float>(r * std::cos(e) * std::cos(a)),
                      static_cast<float>(r * std::cos(e) * std::sin(a)),
                      static_cast<float>(r * std::sin(e)), static_cast<float>(ring));
      if (with_ring) cloud.ring.push_back(static_cast<std::uint16_t>(ring));
    }
  }
  return cloud;
}

std::vector<float> elevations(const PointCloud& cloud) {
  std::vector<float> e(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i)
    e[i] = static_cast<float>(std::atan2(cloud.z[i], std::hypot(cloud.x[i], cloud.y[i])));
  return e;
}

TEST(RingStructure, FromTheRingFieldAndFromElevationsAgree) {
  const std::vector<double> truth = nonuniform_rings_deg();
  const PointCloud cloud = spinning_cloud(truth, 0.2, true);
  const std::vector<float> el = elevations(cloud);
  const auto by_field = rings_from_field(cloud, el.data());
  const auto by_elevation = rings_from_elevations(el.data(), el.size());
  ASSERT_TRUE(by_field);
  ASSERT_TRUE(by_elevation);
  ASSERT_EQ(by_field->rows(), truth.size());
  ASSERT_EQ(by_elevation->rows(), truth.size());
  for (std::size_t row = 0; row < truth.size(); ++row) {
    const double expected = truth[truth.size() - 1 - row] * kDeg;  // row 0 = highest ring
    EXPECT_NEAR(by_field->elevation[row], expected, 1e-6);
    EXPECT_NEAR(by_elevation->elevation[row], expected, 1e-6);
  }
  EXPECT_EQ(by_field->row_of_ring[0], static_cast<int>(truth.size() - 1));
}

TEST(RingStructure, EveryRingOfALargeColumnMajorSweepIsFound) {
  // A 128-channel sweep at 3600 columns, in the drivers' order (every ring of one column, then the
  // next column): 460k points, more than the ring statistics sample. A sampling stride that shares
  // a factor with the channel count would see only some rings and drop the others' points.
  constexpr int kRings = 128, kColumns = 3600;
  PointCloud cloud;
  cloud.reserve(static_cast<std::size_t>(kRings) * kColumns, true);
  std::vector<float> el;
  for (int col = 0; col < kColumns; ++col) {
    const double a = (col + 0.5) * 2 * M_PI / kColumns;
    for (int ring = 0; ring < kRings; ++ring) {
      const double e = (-22.5 + 45.0 * ring / (kRings - 1)) * kDeg, r = 8.0;
      cloud.push_back(static_cast<float>(r * std::cos(e) * std::cos(a)),
                      static_cast<float>(r * std::cos(e) * std::sin(a)),
                      static_cast<float>(r * std::sin(e)), 10.0f);
      cloud.ring.push_back(static_cast<std::uint16_t>(ring));
      el.push_back(static_cast<float>(e));
    }
  }
  const auto rings = rings_from_field(cloud, el.data());
  ASSERT_TRUE(rings);
  ASSERT_EQ(rings->rows(), static_cast<std::size_t>(kRings));
  for (int ring = 0; ring < kRings; ++ring) {
    const int row = rings->row_of_ring[static_cast<std::size_t>(ring)];
    ASSERT_EQ(row, kRings - 1 - ring) << ring;
    EXPECT_NEAR(rings->elevation[static_cast<std::size_t>(row)], el[static_cast<std::size_t>(ring)],
                1e-6);
  }
}

// rings_from_field as its header defines it, point by point: each ring's mean over its finite
// elevations, again over those within 0.5 deg of that mean (3 needed), rows by falling elevation,
// and 90 % of the points within a quarter of the gap to the nearer neighbouring ring. Points are
// sampled as the library samples them (every `stride`-th, every point for a sparse ring).
std::optional<RingStructure> rings_by_definition(const PointCloud& cloud, const float* el) {
  const std::size_t n = cloud.size();
  std::size_t ids = 0;
  for (std::uint16_t r : cloud.ring) ids = std::max<std::size_t>(ids, r + 1u);
  std::size_t stride = (n + 32767) / 32768;
  if (stride > 1)
    while (std::gcd(stride, 210 * ids) != 1) ++stride;
  std::vector<double> mean(ids);
  std::vector<int> near(ids);
  const auto means = [&](std::size_t step) {
    std::vector<double> sum(ids, 0);
    std::vector<int> count(ids, 0);
    for (std::size_t i = 0; i < n; i += step)
      if (std::isfinite(el[i])) sum[cloud.ring[i]] += el[i], ++count[cloud.ring[i]];
    for (std::size_t r = 0; r < ids; ++r) mean[r] = count[r] ? sum[r] / count[r] : 0;
    std::fill(sum.begin(), sum.end(), 0);
    std::fill(near.begin(), near.end(), 0);
    for (std::size_t i = 0; i < n; i += step)
      if (std::fabs(el[i] - mean[cloud.ring[i]]) <= 0.5 * kDeg)
        sum[cloud.ring[i]] += el[i], ++near[cloud.ring[i]];
    for (std::size_t r = 0; r < ids; ++r)
      if (near[r]) mean[r] = sum[r] / near[r];
  };
  means(stride);
  std::vector<int> points(ids, 0);
  for (std::uint16_t r : cloud.ring) ++points[r];
  bool sparse = false;
  for (std::size_t r = 0; r < ids; ++r) sparse |= stride > 1 && points[r] >= 3 && near[r] < 3;
  if (sparse) means(1);
  std::vector<std::size_t> kept;
  for (std::size_t r = 0; r < ids; ++r)
    if (near[r] >= 3) kept.push_back(r);
  if (kept.size() < 4) return std::nullopt;
  std::sort(kept.begin(), kept.end(), [&](auto a, auto b) { return mean[a] > mean[b]; });
  RingStructure rings;
  rings.row_of_ring.assign(ids, -1);
  for (std::size_t row = 0; row < kept.size(); ++row) {
    rings.elevation.push_back(mean[kept[row]]);
    rings.row_of_ring[kept[row]] = static_cast<int>(row);
    if (row > 0 && rings.elevation[row - 1] - rings.elevation[row] < 0.02 * kDeg)
      return std::nullopt;
  }
  const auto band = [&](std::size_t row) {
    double gap = M_PI;
    if (row > 0) gap = std::min(gap, rings.elevation[row - 1] - rings.elevation[row]);
    if (row + 1 < kept.size()) gap = std::min(gap, rings.elevation[row] - rings.elevation[row + 1]);
    return std::max(0.25 * gap, 0.02 * kDeg);
  };
  std::size_t inside = 0, total = 0;
  for (std::size_t i = 0; i < n; i += stride) {
    if (!std::isfinite(el[i])) continue;
    ++total;
    const int row = rings.row_of_ring[cloud.ring[i]];
    inside += row >= 0 && std::fabs(el[i] - rings.elevation[row]) <= band(row);
  }
  if (total == 0 || inside < 0.9 * total) return std::nullopt;
  return rings;
}

TEST(RingStructure, TheRingFieldGivesTheRingsOfTheirDefinition) {
  // Clean rings (the sums' shortcuts), stray returns over 0.5 deg off (the second mean), points
  // beyond a ring's band (counted one by one, some clouds then rejected), NaN elevations, rings of
  // one or two points, and clouds large enough to be sampled, with a sparse ring among them.
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> unit(0, 1), az(-M_PI, M_PI);
  int found = 0, rejected = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int rings = trial % 6 == 5 ? 31 : 8 + trial % 24;
    const std::size_t points = trial % 5 == 4 ? 70000 : 6000;
    const double spread_deg = trial % 3 == 0 ? 0.0 : unit(rng) * (trial % 3 == 1 ? 0.6 : 1.5);
    const double stray = trial % 4 == 1 ? 0.02 : 0.0;
    PointCloud cloud;
    std::vector<float> el;
    for (std::size_t i = 0; i < points; ++i) {
      int ring = static_cast<int>(i % static_cast<std::size_t>(rings));
      if (trial % 5 == 4 && ring == 0 && i % 997 != 0) ring = 1;  // ring 0 sparse: sampled away
      double e = (-15 + 30.0 * ring / (rings - 1)) * kDeg;
      // Some spreads and strays one-sided: only one extreme strays.
      e += (unit(rng) - (trial % 2 ? 0.5 : 0.0)) * spread_deg * kDeg;
      // A skewed ring: a sixth of its points 0.4 deg high, beyond the band of 1-deg-apart
      // rings on one side only, and still within 0.5 deg of the mean.
      if (trial % 6 == 5 && unit(rng) < 0.16) e += 0.4 * kDeg;
      const double side = trial % 8 == 1 ? 1 : (unit(rng) < 0.5 ? -1 : 1);
      if (unit(rng) < stray) e += side * (0.6 + unit(rng)) * kDeg;
      const double a = az(rng), d = 5 + 20 * unit(rng);
      cloud.push_back(static_cast<float>(d * std::cos(e) * std::cos(a)),
                      static_cast<float>(d * std::cos(e) * std::sin(a)),
                      static_cast<float>(d * std::sin(e)), 10.0f);
      cloud.ring.push_back(static_cast<std::uint16_t>(ring));
      el.push_back(i % 401 == 7 ? std::nanf("") : static_cast<float>(e));
    }
    cloud.push_back(1, 0, 0, 10);  // a ring of one point: no row
    cloud.ring.push_back(static_cast<std::uint16_t>(rings + 3));
    el.push_back(0.0f);
    const auto got = rings_from_field(cloud, el.data());
    const auto expected = rings_by_definition(cloud, el.data());
    ASSERT_EQ(got.has_value(), expected.has_value()) << "trial " << trial;
    if (!got) {
      ++rejected;
      continue;
    }
    ++found;
    EXPECT_EQ(got->elevation, expected->elevation) << "trial " << trial;
    EXPECT_EQ(got->row_of_ring, expected->row_of_ring) << "trial " << trial;
  }
  EXPECT_GT(found, 30);
  EXPECT_GT(rejected, 3);
}

TEST(RingStructure, ARosetteOrLivoxLinesAreNotRings) {
  // Points spread evenly over a 38 deg cone, tagged with six "line" numbers as Livox drivers do.
  PointCloud cloud;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-19 * kDeg, 19 * kDeg);
  for (int i = 0; i < 100000; ++i) {
    const double a = angle(rng), e = angle(rng);
    cloud.push_back(static_cast<float>(std::cos(e) * std::cos(a)),
                    static_cast<float>(std::cos(e) * std::sin(a)), static_cast<float>(std::sin(e)),
                    10);
    cloud.ring.push_back(static_cast<std::uint16_t>(i % 6));
  }
  const std::vector<float> el = elevations(cloud);
  EXPECT_FALSE(rings_from_field(cloud, el.data()));
  EXPECT_FALSE(rings_from_elevations(el.data(), el.size()));
}

TEST(RingRows, GeometryRoundTripsExactlyBetweenAndBeyondRings) {
  ImageGeometry g;
  g.width = 1800;
  g.res_h = 0.2 * kDeg;
  g.u0 = 900;
  const std::vector<double> layout = nonuniform_rings_deg();
  for (auto it = layout.rbegin(); it != layout.rend(); ++it) g.row_elevation.push_back(*it * kDeg);
  g.height = static_cast<int>(g.row_elevation.size());
  g.res_v = (g.row_elevation.front() - g.row_elevation.back()) / (g.height - 1);
  for (int row = 0; row < g.height; ++row)
    EXPECT_NEAR(g.elevation_of_v(row), g.row_elevation[static_cast<std::size_t>(row)], 1e-15);
  for (double v = -2.0; v <= g.height + 1.0; v += 0.0137) {
    EXPECT_NEAR(g.v_of_elevation(g.elevation_of_v(v)), v, 1e-9) << v;
    const Vec3 ray = g.ray(17.3, v);
    EXPECT_NEAR(g.pixel_of_point(5 * ray).y(), v, 1e-9);
  }
  // Monotone: higher elevation, smaller row.
  EXPECT_LT(g.v_of_elevation(10 * kDeg), g.v_of_elevation(9.9 * kDeg));
}

TEST(RingRows, ProjectionGivesEveryRingItsOwnRowWithNoEmptyRow) {
  const std::vector<double> rings = nonuniform_rings_deg();
  for (bool with_ring : {true, false}) {
    const PointCloud cloud = spinning_cloud(rings, 0.2, with_ring);
    ProjectionOptions options;
    options.res_h_deg = 0.2;
    options.res_v_deg = 0.333;
    options.rows = RowLayout::kRings;
    SphericalProjector projector(options);
    ProjectedImage image;
    projector.project(cloud, image);
    EXPECT_EQ(image.row_source, with_ring ? "ring field" : "elevation clusters");
    ASSERT_EQ(image.geometry.height, static_cast<int>(rings.size()));
    EXPECT_EQ(image.points_projected, cloud.size());
    for (int row = 0; row < image.geometry.height; ++row) {
      // 1800 columns, one point each: a full row, no collisions.
      EXPECT_EQ(cv::countNonZero(image.mask.row(row)), image.geometry.width) << "row " << row;
      EXPECT_EQ(cv::countNonZero(image.count.row(row) > 1), 0) << "row " << row;
    }
    // With uniform rows at the finest spacing the sparse rings leave empty rows.
    options.rows = RowLayout::kUniform;
    SphericalProjector uniform(options);
    uniform.project(cloud, image);
    int empty_rows = 0;
    for (int row = 0; row < image.geometry.height; ++row)
      empty_rows += cv::countNonZero(image.mask.row(row)) == 0;
    EXPECT_GT(empty_rows, 30);
  }
}

// A VLP-16 sweep as real drivers give it: from +180 deg round to just short of -180, every other
// ring fired 0.75 of a column after the one below (its firing stagger), so their last samples lie
// 0.05 deg from where the sweep began. The image has one turn of columns (not one more, which
// showed the first column's direction twice beside the seam: the real Pandar64 frames in
// ../shared/data/real gave 1801 columns of 0.2 deg), every sample has its own pixel, and the
// projection records where the staggered rings' samples lie, the ones past the seam included.
TEST(RingRows, ASweepAllRoundHasOneTurnOfColumnsAndKeepsWhereItsSamplesLie) {
  PointCloud cloud;
  for (int ring = 0; ring < 16; ++ring) {
    const double elevation = (-15 + 2 * ring) * kDeg, lag = ring % 2 == 1 ? 0.15 : 0;
    for (int c = 0; c < 1800; ++c) {
      const double azimuth = (180 - 0.2 * c - lag) * kDeg;
      cloud.push_back(static_cast<float>(8 * std::cos(elevation) * std::cos(azimuth)),
                      static_cast<float>(8 * std::cos(elevation) * std::sin(azimuth)),
                      static_cast<float>(8 * std::sin(elevation)), 50.f);
      cloud.ring.push_back(static_cast<std::uint16_t>(ring));
    }
  }
  ProjectionOptions options;
  options.res_h_deg = 0.2;
  options.res_v_deg = 2;
  options.rows = RowLayout::kRings;
  ProjectedImage image;
  SphericalProjector(options).project(cloud, image);
  EXPECT_EQ(image.row_source, "ring field");
  ASSERT_EQ(image.geometry.width, 1800);
  ASSERT_EQ(image.geometry.height, 16);
  EXPECT_TRUE(image.geometry.full_circle());
  EXPECT_EQ(image.points_projected, cloud.size());
  EXPECT_EQ(cv::countNonZero(image.count == 1), 16 * 1800);
  // Row 0 is ring 15, a staggered one: u = c + 0.75, so column c + 1 and 0.25 left of its
  // centre; its last sample wraps to column 0.
  ASSERT_FALSE(image.column_offset.empty());
  for (int row = 0; row < 16; ++row) {
    const double expected = row % 2 == 0 ? -0.25 : 0;
    for (int c = 0; c < 1800; ++c)
      ASSERT_NEAR(image.column_offset.at<float>(row, c), expected, 2e-3) << row << " " << c;
  }
  EXPECT_EQ(image.index.at<int>(0, 0), 16 * 1800 - 1);
  EXPECT_EQ(image.index.at<int>(0, 1), 15 * 1800);
  EXPECT_EQ(image.index.at<int>(15, 0), 0);
  // Uniform rows in a preset's full field (-180..180 deg): one turn of columns too, none lost.
  options.rows = RowLayout::kUniform;
  options.field_of_view = AngularBounds{-M_PI, M_PI, -16 * kDeg, 16 * kDeg};
  SphericalProjector(options).project(cloud, image);
  EXPECT_EQ(image.geometry.width, 1800);
  EXPECT_EQ(image.points_projected, cloud.size());
  EXPECT_TRUE(image.column_offset.empty());
}

TEST(SquarePixels, CornersMapBackToTheProjectedImageExactly) {
  // VLP-16: uniform 2 deg rows; and the non-uniform ring rows.
  ImageGeometry vlp16 =
      geometry_for_bounds({-M_PI, M_PI, -15 * kDeg, 15 * kDeg}, 0.2 * kDeg, 2 * kDeg);
  ImageGeometry rings = vlp16;
  const std::vector<double> layout = nonuniform_rings_deg();
  for (auto it = layout.rbegin(); it != layout.rend(); ++it)
    rings.row_elevation.push_back(*it * kDeg);
  rings.height = static_cast<int>(rings.row_elevation.size());
  for (const ImageGeometry& g : {vlp16, rings}) {
    ASSERT_TRUE(needs_square_pixels(g));
    const ImageGeometry square = square_pixel_geometry(g);
    EXPECT_NEAR(square.res_v, square.res_h, 1e-12);
    EXPECT_EQ(square.width, g.width);
    EXPECT_GT(square.height, 4 * g.height);
    for (double v = 0; v <= g.height - 1; v += 0.173) {
      const Vec2 px(411.37, v);
      const Vec2 there = map_pixel(px, g, square), back = map_pixel(there, square, g);
      EXPECT_NEAR(back.x(), px.x(), 1e-9);
      EXPECT_NEAR(back.y(), px.y(), 1e-9);
      EXPECT_NEAR(there.x(), px.x(), 1e-9);  // columns are shared
      // Both land on the same direction.
      EXPECT_LT((square.ray(there) - g.ray(px)).norm(), 1e-12);
    }
  }
  // Square pixels are left alone.
  const ImageGeometry mid40 = geometry_for_bounds({-0.3, 0.3, -0.3, 0.3}, 0.05 * kDeg, 0.05 * kDeg);
  EXPECT_FALSE(needs_square_pixels(mid40));
}

TEST(SquarePixels, RowsTakeTheNearerRingSoEdgesFallHalfWay) {
  // Two rings 2 deg apart: black above, white below. The resampled edge lies half-way.
  ImageGeometry g = geometry_for_bounds({-0.1, 0.1, -1 * kDeg, 1 * kDeg}, 0.2 * kDeg, 2 * kDeg);
  ASSERT_EQ(g.height, 2);
  cv::Mat image(2, g.width, CV_32F), valid(2, g.width, CV_8U, cv::Scalar(255));
  image.row(0).setTo(10);
  image.row(1).setTo(120);
  const ImageGeometry square = square_pixel_geometry(g);
  cv::Mat out, out_valid;
  resample_rows(image, valid, g, square, out, out_valid);
  ASSERT_EQ(out.rows, square.height);
  for (int r = 0; r < out.rows; ++r) {
    const double elevation = square.elevation_of_v(r);
    EXPECT_EQ(out.at<float>(r, 3), elevation > 1e-9 ? 10.f : 120.f) << r;
  }
  EXPECT_EQ(cv::countNonZero(out_valid), out.rows * out.cols);
}

}  // namespace
}  // namespace iilfm
