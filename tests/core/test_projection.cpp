#include <gtest/gtest.h>

#include <random>
#include <string>

#include "../../src/projection_passes.hpp"
#include "iilfm/error.hpp"
#include "iilfm/projection.hpp"

namespace iilfm {
namespace {

constexpr double kDeg = M_PI / 180.0;

PointCloud cloud_of(const std::vector<Vec3>& points, float intensity = 100) {
  PointCloud cloud;
  for (const Vec3& p : points) cloud.push_back(p.x(), p.y(), p.z(), intensity);
  return cloud;
}

TEST(ImageGeometry, PointToPixelToRayRoundTrips) {
  ImageGeometry g = geometry_for_bounds({-M_PI, M_PI, -0.4, 0.3}, 0.2 * kDeg, 2 * kDeg);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> az(-M_PI + 1e-6, M_PI), el(-0.4, 0.3), r(0.5, 80);
  for (int i = 0; i < 1000; ++i) {
    const double a = az(rng), e = el(rng);
    const Vec3 p = r(rng) * Vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
    const Vec2 uv = g.pixel_of_point(p);
    EXPECT_LT((g.ray(uv) - p.normalized()).norm(), 1e-12);
    EXPECT_NEAR(g.azimuth_of_u(uv.x()), a, 1e-12);
    EXPECT_NEAR(g.elevation_of_v(uv.y()), e, 1e-12);
  }
}

TEST(ImageGeometry, IsNotMirrored) {
  // Looking along +x: a point to the left (+y) is left in the image, a point above is higher.
  const ImageGeometry g = geometry_for_bounds({-0.5, 0.5, -0.5, 0.5}, 0.01, 0.01);
  const Vec2 centre = g.pixel_of_point(Vec3(5, 0, 0));
  const Vec2 left = g.pixel_of_point(Vec3(5, 1, 0));
  const Vec2 up = g.pixel_of_point(Vec3(5, 0, 1));
  EXPECT_LT(left.x(), centre.x());
  EXPECT_NEAR(left.y(), centre.y(), 1e-12);
  EXPECT_LT(up.y(), centre.y());
  EXPECT_NEAR(up.x(), centre.x(), 1e-12);
}

TEST(ImageGeometry, SizeFollowsTheAngularExtent) {
  const ImageGeometry g =
      geometry_for_bounds({-10 * kDeg, 10 * kDeg, -5 * kDeg, 5 * kDeg}, 0.5 * kDeg, 0.25 * kDeg);
  EXPECT_EQ(g.width, 41);
  EXPECT_EQ(g.height, 41);
  EXPECT_NEAR(g.pixel_of_angles(10 * kDeg, 5 * kDeg).x(), 0, 1e-9);
  EXPECT_NEAR(g.pixel_of_angles(-10 * kDeg, -5 * kDeg).y(), 40, 1e-9);
}

TEST(SphericalProjector, BinsPointsWithMeanAndNearestPolicies) {
  // Two points in the same pixel at 4 m and 4.2 m, one more elsewhere to span the image.
  const std::vector<Vec3> pts = {Vec3(4, 0, 0), Vec3(4.2, 0.0001, 0), Vec3(4, 0.3, 0.3)};
  PointCloud cloud = cloud_of(pts);
  cloud.intensity = {10, 30, 50};
  ProjectionOptions opt;
  opt.res_h_deg = opt.res_v_deg = 0.5;
  ProjectedImage img;
  SphericalProjector(opt).project(cloud, img);
  const Vec2 uv = img.geometry.pixel_of_point(pts[0]);
  const int c = static_cast<int>(std::lround(uv.x())), r = static_cast<int>(std::lround(uv.y()));
  EXPECT_EQ(img.count.at<int>(r, c), 2);
  EXPECT_NEAR(img.range.at<float>(r, c), (4.0 + std::hypot(4.2, 0.0001)) / 2, 1e-5);
  EXPECT_NEAR(img.intensity.at<float>(r, c), 20, 1e-5);
  EXPECT_EQ(img.index.at<int>(r, c), 1);  // the last of the pixel's points
  EXPECT_EQ(cv::countNonZero(img.mask), 2);
  EXPECT_EQ(img.points_projected, 3u);

  // The nearest point, whatever its place in the cloud: first, then last.
  opt.collision = CollisionPolicy::kNearest;
  SphericalProjector(opt).project(cloud, img);
  EXPECT_NEAR(img.range.at<float>(r, c), 4.0, 1e-6);
  EXPECT_NEAR(img.intensity.at<float>(r, c), 10, 1e-6);
  EXPECT_EQ(img.index.at<int>(r, c), 0);
  EXPECT_EQ(img.count.at<int>(r, c), 2);
  std::swap(cloud.x[0], cloud.x[1]);
  std::swap(cloud.y[0], cloud.y[1]);
  std::swap(cloud.intensity[0], cloud.intensity[1]);
  SphericalProjector(opt).project(cloud, img);
  EXPECT_NEAR(img.range.at<float>(r, c), 4.0, 1e-6);
  EXPECT_NEAR(img.intensity.at<float>(r, c), 10, 1e-6);
  EXPECT_EQ(img.index.at<int>(r, c), 1);
}

TEST(SphericalProjector, UsesThePresetFieldOfViewWhenTheCloudFitsInIt) {
  const PointCloud cloud = cloud_of({Vec3(3, 0.1, 0.1), Vec3(3, -0.1, -0.1)});
  ProjectionOptions opt;
  opt.res_h_deg = opt.res_v_deg = 0.05;
  opt.field_of_view = AngularBounds{-19.2 * kDeg, 19.2 * kDeg, -19.2 * kDeg, 19.2 * kDeg};
  ProjectedImage img;
  SphericalProjector(opt).project(cloud, img);
  EXPECT_EQ(img.geometry.width, 769);
  EXPECT_EQ(img.geometry.height, 769);
  // A point outside the preset's window: the image grows to the cloud instead of dropping it.
  const PointCloud wide = cloud_of({Vec3(3, 0.1, 0.1), Vec3(0, 3, 0)});
  SphericalProjector(opt).project(wide, img);
  EXPECT_EQ(img.points_projected, 2u);
}

TEST(SphericalProjector, RefusesAbsurdImageSizes) {
  const PointCloud cloud = cloud_of({Vec3(1, 1, 1), Vec3(1, -1, -1)});
  ProjectionOptions opt;
  opt.res_h_deg = opt.res_v_deg = 0.0001;
  ProjectedImage img;
  try {
    SphericalProjector(opt).project(cloud, img);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--res-h"), std::string::npos);
  }
  opt.res_h_deg = 0;
  EXPECT_THROW(SphericalProjector{opt}, InputError);
}

TEST(SphericalProjector, EmptyCloudGivesAOnePixelUnobservedImage) {
  ProjectionOptions opt;
  ProjectedImage img;
  SphericalProjector(opt).project(PointCloud{}, img);
  EXPECT_EQ(cv::countNonZero(img.mask), 0);
  EXPECT_EQ(img.points_projected, 0u);
}

// Every image of `a` equals the one of `b`, pixel for pixel.
void expect_same_images(const ProjectedImage& a, const ProjectedImage& b, const std::string& what) {
  ASSERT_EQ(a.geometry.width, b.geometry.width) << what;
  ASSERT_EQ(a.geometry.height, b.geometry.height) << what;
  EXPECT_EQ(cv::norm(a.count, b.count, cv::NORM_INF), 0) << what;
  EXPECT_EQ(cv::norm(a.index, b.index, cv::NORM_INF), 0) << what;
  EXPECT_EQ(cv::norm(a.mask, b.mask, cv::NORM_INF), 0) << what;
  EXPECT_EQ(cv::norm(a.range, b.range, cv::NORM_INF), 0) << what;
  EXPECT_EQ(cv::norm(a.intensity, b.intensity, cv::NORM_INF), 0) << what;
  EXPECT_EQ(a.points_projected, b.points_projected) << what;
}

TEST(PixelsOfPoints, PutsEveryPointInThePixelOfItsAngles) {
  // The vectorised pass against the double-precision geometry: inside points in the pixel whose
  // centre is nearest (ties within float rounding aside), outside and unmeasured points at -1.
  const ImageGeometry g =
      geometry_for_bounds({-20 * kDeg, 20 * kDeg, -10 * kDeg, 15 * kDeg}, 0.1 * kDeg, 0.2 * kDeg);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> az(-25 * kDeg, 25 * kDeg), el(-14 * kDeg, 19 * kDeg);
  const std::size_t n = 20000;
  std::vector<float> azimuth(n), elevation(n), range(n, 5.0f);
  std::vector<std::int32_t> pixel(n);
  for (std::size_t i = 0; i < n; ++i) azimuth[i] = az(rng), elevation[i] = el(rng);
  range[7] = 0;  // unmeasured
  range[8] = std::numeric_limits<float>::quiet_NaN();
  elevation[9] = std::numeric_limits<float>::quiet_NaN();
  const std::int32_t row_stride = g.width + 7;  // the accumulators' rows are padded
  const std::size_t outside = detail::pixels_of_points(
      g, row_stride, azimuth.data(), elevation.data(), range.data(), n, pixel.data());
  std::size_t expected_outside = 0, checked = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 uv = g.pixel_of_angles(azimuth[i], elevation[i]);
    const bool in = range[i] > 0 && uv.x() >= -0.5 && uv.y() >= -0.5 && uv.x() < g.width - 0.5 &&
                    uv.y() < g.height - 0.5;
    if (!in) {
      ++expected_outside;
      EXPECT_EQ(pixel[i], -1) << i;
      continue;
    }
    const double du = uv.x() - std::round(uv.x()), dv = uv.y() - std::round(uv.y());
    if (std::abs(std::abs(du) - 0.5) < 1e-3 || std::abs(std::abs(dv) - 0.5) < 1e-3) continue;
    ++checked;
    EXPECT_EQ(pixel[i], std::lround(uv.y()) * row_stride + std::lround(uv.x())) << i;
  }
  EXPECT_EQ(outside, expected_outside);
  EXPECT_GT(checked, n / 2);
  EXPECT_GT(expected_outside, n / 10);
}

TEST(SphericalProjector, AReusedProjectorGivesTheImagesOfAFreshOne) {
  // The projector clears its per-pixel sums as it writes the images; a smaller image between two
  // large ones must leave nothing behind in either.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> az(-0.3, 0.3), el(-0.2, 0.2), r(2, 9);
  auto cloud_in = [&](double scale, int points) {
    PointCloud cloud;
    for (int i = 0; i < points; ++i) {
      const double a = scale * az(rng), e = scale * el(rng), d = r(rng);
      cloud.push_back(d * std::cos(e) * std::cos(a), d * std::cos(e) * std::sin(a), d * std::sin(e),
                      static_cast<float>(d * 10));
    }
    return cloud;
  };
  const PointCloud large = cloud_in(1.0, 40000), small = cloud_in(0.3, 500);
  for (CollisionPolicy policy : {CollisionPolicy::kMean, CollisionPolicy::kNearest}) {
    ProjectionOptions opt;
    opt.res_h_deg = opt.res_v_deg = 0.2;
    opt.collision = policy;
    SphericalProjector reused(opt);
    ProjectedImage image;
    for (const PointCloud* cloud : {&large, &small, &large, &small}) {
      reused.project(*cloud, image);
      ProjectedImage fresh;
      SphericalProjector(opt).project(*cloud, fresh);
      expect_same_images(image, fresh, "reused");
      EXPECT_EQ(image.points_projected, cloud->size());
    }
  }
}

TEST(SphericalProjector, ThreadsGiveTheImagesOfOneThread) {
  // Large enough for every pass to split (200k points, 600 x 400 pixels), with many points per
  // pixel so that the order in which a pixel's points are added matters for its sums, for
  // uniform and ring rows and both collision policies.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> az(-0.5, 0.5), r(2, 30);
  std::uniform_int_distribution<int> ring_of(0, 15);
  PointCloud cloud;
  cloud.ring.clear();
  for (int i = 0; i < 200000; ++i) {
    const int ring = ring_of(rng);
    const double a = az(rng), e = (ring - 7.5) * 2 * kDeg, d = r(rng);
    cloud.push_back(d * std::cos(e) * std::cos(a), d * std::cos(e) * std::sin(a), d * std::sin(e),
                    static_cast<float>(d * 3));
    cloud.ring.push_back(static_cast<std::uint16_t>(ring));
  }
  for (RowLayout rows : {RowLayout::kUniform, RowLayout::kRings}) {
    for (CollisionPolicy policy : {CollisionPolicy::kMean, CollisionPolicy::kNearest}) {
      ProjectionOptions opt;
      opt.res_h_deg = 0.1;
      opt.res_v_deg = 0.1;
      opt.rows = rows;
      opt.collision = policy;
      ProjectedImage one;
      SphericalProjector(opt).project(cloud, one);
      for (int threads : {2, 3, 64}) {
        opt.threads = threads;
        ProjectedImage many;
        SphericalProjector(opt).project(cloud, many);
        expect_same_images(many, one, std::to_string(threads) + " threads");
      }
      EXPECT_EQ(one.points_projected, cloud.size());
      EXPECT_GT(cv::countNonZero(one.count > 3), 1000);  // pixels whose sums depend on order
    }
  }
}

TEST(SphericalProjector, ARingFieldInAnyLayoutGivesTheSameImages) {
  // A contiguous ring field is read in place, a strided one (a numpy record array) copied first:
  // the same pixels for every point, including points on the seam's two edges, rings with too
  // few points for a row, NaN and zero points.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> az(-M_PI, M_PI), r(1, 40), jitter(-0.05, 0.05);
  std::uniform_int_distribution<int> ring_of(0, 31);
  PointCloud cloud;
  const auto add = [&](double a, double e, double d, int ring) {
    cloud.push_back(d * std::cos(e) * std::cos(a), d * std::cos(e) * std::sin(a), d * std::sin(e),
                    static_cast<float>(d));
    cloud.ring.push_back(static_cast<std::uint16_t>(ring));
  };
  for (int i = 0; i < 30000; ++i) {
    const int ring = ring_of(rng);
    add(az(rng), (ring - 15.5) * 1.0 * kDeg + jitter(rng) * kDeg, r(rng), ring);
  }
  for (double a : {M_PI, -M_PI, std::nextafter(M_PI, 0.0), 0.0}) add(a, 0.5 * kDeg, 5, 16);
  add(0.3, 40 * kDeg, 5, 40);  // a ring seen twice: no row
  add(0.4, 41 * kDeg, 5, 40);
  add(0.5, 2 * kDeg, 5, 1000);  // a lone ring far past the others: no row
  cloud.push_back(std::nanf(""), 1, 1, 5);
  cloud.ring.push_back(3);
  cloud.push_back(0, 0, 0, 5);
  cloud.ring.push_back(3);

  // The same points with the ring field every other entry of a larger array.
  std::vector<std::uint16_t> interleaved(2 * cloud.size(), 7);
  for (std::size_t i = 0; i < cloud.size(); ++i) interleaved[2 * i] = cloud.ring[i];
  PointView strided(cloud);
  strided.ring = StridedColumn<std::uint16_t>{interleaved.data(), 2};

  for (bool preset_view : {false, true}) {
    ProjectionOptions opt;
    opt.res_h_deg = 0.2;
    opt.res_v_deg = 1.0;
    opt.rows = RowLayout::kRings;
    if (preset_view) opt.field_of_view = AngularBounds{-M_PI, M_PI, -45 * kDeg, 45 * kDeg};
    ProjectedImage fast, scalar;
    SphericalProjector(opt).project(cloud, fast);
    SphericalProjector(opt).project(strided, scalar);
    EXPECT_EQ(fast.row_source, "ring field");
    expect_same_images(fast, scalar, preset_view ? "preset field of view" : "cloud's extent");
    EXPECT_EQ(fast.geometry.height, 32);
    // Every point is binned but the NaN and zero ones and the three without a row.
    EXPECT_EQ(fast.points_projected, cloud.size() - 5);
  }
}

}  // namespace
}  // namespace iilfm
