#include <gtest/gtest.h>

#include <random>

#include "iilfm/lift.hpp"

namespace iilfm {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A tilted plane n.x = d sampled at every pixel centre of a 41x41 image at 0.5 deg, except for
// the pixels of column 20 within `hole_radius_rows` of row 20 (none when negative).
struct PlaneScene {
  Vec3 normal = Vec3(-1, 0.3, 0.4).normalized();
  double d = -3.0;  // n.x = d, about 3 m in front of the sensor
  ProjectedImage image;

  Vec3 hit(const Vec3& ray) const { return ray * (d / normal.dot(ray)); }

  explicit PlaneScene(int hole_radius_rows) {
    const ImageGeometry g =
        geometry_for_bounds({-10 * kDeg, 10 * kDeg, -10 * kDeg, 10 * kDeg}, 0.5 * kDeg, 0.5 * kDeg);
    PointCloud cloud;
    for (int r = 0; r < g.height; ++r)
      for (int c = 0; c < g.width; ++c) {
        if (c == 20 && std::abs(r - 20) <= hole_radius_rows) continue;
        const Vec3 p = hit(g.ray(c, r));
        cloud.push_back(p.x(), p.y(), p.z(), 100);
      }
    ProjectionOptions opt;
    opt.res_h_deg = opt.res_v_deg = 0.5;
    SphericalProjector(opt).project(cloud, image);
  }
};

TEST(LiftPaper, ObservedKeypointUsesItsRangeAlongTheSubPixelRay) {
  PlaneScene scene(-1);
  const Vec2 px(5.2, 7.9);
  const LiftedCorner c = lift_paper(px, scene.image);
  ASSERT_EQ(c.status, CornerStatus::kObserved);
  EXPECT_LT((c.point.normalized() - scene.image.geometry.ray(px)).norm(), 1e-12);
  EXPECT_NEAR(c.point.norm(), scene.image.range.at<float>(8, 5), 1e-5);
}

TEST(LiftPaper, AngleBisectorRuleMatchesTheHandComputedPlanePoint) {
  for (int hole : {-1, 0, 2, 4}) {
    PlaneScene scene(hole);
    const Vec2 px(20, 20);
    const LiftedCorner c = lift_paper(px, scene.image);
    ASSERT_EQ(c.status, hole < 0 ? CornerStatus::kObserved : CornerStatus::kInterpolated);
    const Vec3 truth = scene.hit(scene.image.geometry.ray(px));
    EXPECT_LT((c.point - truth).norm(), 1e-5) << "hole " << hole;  // float32 cloud: ~1 ppm

    if (hole == 4) {
      // The paper's printed weights (mu/(1+mu) on p_d) land off the plane point by millimetres
      // on this tilted plane: the test can tell the two forms apart.
      const Vec3 pu = pixel_point(scene.image, 20, 15), pd = pixel_point(scene.image, 20, 25);
      const double mu = pd.norm() / pu.norm();
      const Vec3 printed = mu / (1 + mu) * pd + 1 / (1 + mu) * pu;
      EXPECT_GT((printed - truth).norm(), 1e-3);
    }
  }
}

TEST(LiftPaper, NoSymmetricPairMeansUnrecoverable) {
  PlaneScene scene(30);  // the whole column is missing, and the row pair lies beyond reach
  LiftOptions opt;
  opt.max_pair_distance_px = 0;
  const LiftedCorner c = lift_paper(Vec2(20, 20), scene.image, opt);
  EXPECT_EQ(c.status, CornerStatus::kUnrecoverable);
  EXPECT_FALSE(c.valid());
  // With the row fallback in reach it is recovered from the neighbours left and right.
  const LiftedCorner row = lift_paper(Vec2(20, 20), scene.image);
  ASSERT_EQ(row.status, CornerStatus::kInterpolated);
  const Vec3 truth = scene.hit(scene.image.geometry.ray(20, 20));
  EXPECT_LT((row.point - truth).norm(), 1e-3);  // the row pair is not exactly symmetric in angle
  EXPECT_EQ(lift_paper(Vec2(-50, 3), scene.image).status, CornerStatus::kUnrecoverable);
  EXPECT_EQ(lift_paper(Vec2(NAN, 3), scene.image).status, CornerStatus::kUnrecoverable);
}

}  // namespace
}  // namespace iilfm

namespace iilfm {
namespace {

// A marker quad (pixels 15..25 of a 41x41 image at 0.5 deg) on plane `inner`, everything else on
// plane `outer`, with Gaussian range noise.
struct SheetOnWall {
  ProjectedImage image;
  PointCloud cloud;
  std::vector<Vec2> quad = {Vec2(15, 15), Vec2(25, 15), Vec2(25, 25), Vec2(15, 25)};

  // `inner_noise_m` < 0: the marker's noise is the wall's.
  SheetOnWall(const Vec3& inner_normal, double inner_d, const Vec3& outer_normal, double outer_d,
              double noise_m, unsigned seed, double inner_noise_m = -1) {
    const ImageGeometry g =
        geometry_for_bounds({-10 * kDeg, 10 * kDeg, -10 * kDeg, 10 * kDeg}, 0.5 * kDeg, 0.5 * kDeg);
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0, 1);
    for (int r = 0; r < g.height; ++r)
      for (int c = 0; c < g.width; ++c) {
        const bool inside = c >= 15 && c <= 25 && r >= 15 && r <= 25;
        const Vec3& n = inside ? inner_normal : outer_normal;
        const double sigma = inside && inner_noise_m >= 0 ? inner_noise_m : noise_m;
        const Vec3 ray = g.ray(c, r);
        const double t =
            (inside ? inner_d : outer_d) / n.dot(ray) + (sigma > 0 ? sigma * noise(rng) : 0);
        const Vec3 p = ray * t;
        cloud.push_back(p.x(), p.y(), p.z(), 100);
      }
    ProjectionOptions opt;
    opt.res_h_deg = opt.res_v_deg = 0.5;
    SphericalProjector(opt).project(cloud, image);
  }
};

const Vec3 kWallNormal = Vec3(-1, 0.2, 0.1).normalized();

TEST(MarkerPlane, CoplanarSurroundIsUsedAndSharpensTheNormal) {
  double error_marker_only = 0, error_with_surround = 0;
  PlaneFitOptions marker_only;
  marker_only.surround_scales.clear();
  for (unsigned seed = 0; seed < 20; ++seed) {
    const SheetOnWall scene(kWallNormal, -3.0, kWallNormal, -3.0, 0.02, seed);
    const Plane wide = fit_marker_plane(scene.quad, scene.image, scene.cloud);
    const Plane narrow = fit_marker_plane(scene.quad, scene.image, scene.cloud, marker_only);
    ASSERT_TRUE(wide.ok && narrow.ok);
    EXPECT_EQ(wide.surround_scale, 3.0);
    EXPECT_EQ(narrow.surround_scale, 1.0);
    error_with_surround += std::acos(std::min(1.0, std::abs(wide.normal.dot(kWallNormal))));
    error_marker_only += std::acos(std::min(1.0, std::abs(narrow.normal.dot(kWallNormal))));
  }
  EXPECT_LT(error_with_surround, 0.4 * error_marker_only);
}

TEST(MarkerPlane, WallNoisierThanTheMarkerIsTakenOnItsOwnPlane) {
  // The marker's pixels average more returns than the wall's (a rosette is densest at its centre):
  // 8 mm noise on the marker, 2.5 cm on the wall. A third of the wall lies outside the marker's
  // band, so the coplanar test fails, but the wall's own plane holds the marker.
  double error_marker_only = 0, error_with_surround = 0;
  PlaneFitOptions marker_only;
  marker_only.surround_scales.clear();
  for (unsigned seed = 0; seed < 10; ++seed) {
    const SheetOnWall scene(kWallNormal, -3.0, kWallNormal, -3.0, 0.025, seed, 0.008);
    const Plane wide = fit_marker_plane(scene.quad, scene.image, scene.cloud);
    const Plane narrow = fit_marker_plane(scene.quad, scene.image, scene.cloud, marker_only);
    ASSERT_TRUE(wide.ok && narrow.ok);
    EXPECT_EQ(wide.surround_scale, 3.0) << seed;
    error_with_surround += std::acos(std::min(1.0, std::abs(wide.normal.dot(kWallNormal))));
    error_marker_only += std::acos(std::min(1.0, std::abs(narrow.normal.dot(kWallNormal))));
  }
  EXPECT_LT(error_with_surround, 0.6 * error_marker_only);
}

TEST(MarkerPlane, SurroundOnAnotherPlaneIsIgnored) {
  const Vec3 turned = Vec3(-1, -0.3, 0.1).normalized();  // about 28 deg away
  const SheetOnWall tilted(kWallNormal, -3.0, turned, -3.0, 0.0, 1);
  const Plane p = fit_marker_plane(tilted.quad, tilted.image, tilted.cloud);
  ASSERT_TRUE(p.ok);
  EXPECT_EQ(p.surround_scale, 1.0);
  EXPECT_LT(std::acos(std::min(1.0, std::abs(p.normal.dot(kWallNormal)))), 1e-4);
}

TEST(MarkerPlane, ParallelSurroundSetsTheNormalButNotTheDepth) {
  // A sheet 5 cm proud of its wall, 2 cm range noise: the wall's points fall inside the inlier
  // band, so the normal comes from both, while the depth must stay the sheet's own.
  const SheetOnWall board(kWallNormal, -3.0, kWallNormal, -3.05, 0.02, 2);
  const Plane p = fit_marker_plane(board.quad, board.image, board.cloud);
  ASSERT_TRUE(p.ok);
  EXPECT_NEAR(p.d * (p.normal.dot(kWallNormal) > 0 ? 1 : -1), -3.0, 0.005);
}

// A 17 cm marker at 1 m seen by a VLP-16-like sensor (0.2 x 2 deg pixels): four rows cross it.
// The wall has Gaussian range noise; the marker's rows are offset by `row_offsets_m` (top row
// first) on top of it: a sheet turned away from the wall, or a chance draw of noise that tilts a
// plane fitted to four rows.
struct FewRowsOnWall {
  ProjectedImage image;
  PointCloud cloud;
  std::vector<Vec2> quad;

  FewRowsOnWall(const std::vector<double>& row_offsets_m, double noise_m, unsigned seed) {
    const ImageGeometry g =
        geometry_for_bounds({-20 * kDeg, 20 * kDeg, -15 * kDeg, 15 * kDeg}, 0.2 * kDeg, 2 * kDeg);
    const double cu = (g.width - 1) / 2.0, cv = (g.height - 1) / 2.0;  // cv: between two rows
    quad = {Vec2(cu - 24.5, cv - 1.9), Vec2(cu + 24.5, cv - 1.9), Vec2(cu + 24.5, cv + 1.9),
            Vec2(cu - 24.5, cv + 1.9)};
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0, noise_m);
    const int top = static_cast<int>(std::ceil(cv - 1.9));
    for (int r = 0; r < g.height; ++r)
      for (int c = 0; c < g.width; ++c) {
        const Vec3 ray = g.ray(c, r);
        double t = -1.0 / kWallNormal.dot(ray) + noise(rng);
        const auto row = static_cast<std::size_t>(r - top);
        if (std::abs(c - cu) < 24.5 && r >= top && row < row_offsets_m.size())
          t += row_offsets_m[row];
        const Vec3 p = ray * t;
        cloud.push_back(p.x(), p.y(), p.z(), 100);
      }
    ProjectionOptions opt;
    opt.res_h_deg = 0.2;
    opt.res_v_deg = 2;
    SphericalProjector(opt).project(cloud, image);
  }
};

double angle_to_wall(const Plane& p) {
  return std::acos(std::min(1.0, std::abs(p.normal.dot(kWallNormal)))) / kDeg;
}

TEST(MarkerPlane, WallIsTakenWhenFewRowsTiltTheMarkersOwnPlane) {
  // 2.5 cm noise (a VLP-16's) and the rows' mean offsets of a simulated VLP-16 sweep whose pose
  // was 32 cm off: the marker's own plane tilts and the wall lies off it, but the marker's points
  // lie within the wall's noise, and its tilt within a chance draw of it.
  const std::vector<double> tilt = {-0.01, 0.0, 0.004, 0.012};
  PlaneFitOptions marker_only;
  marker_only.surround_scales.clear();
  for (unsigned seed = 0; seed < 10; ++seed) {
    const FewRowsOnWall scene(tilt, 0.025, seed);
    const Plane own = fit_marker_plane(scene.quad, scene.image, scene.cloud, marker_only);
    const Plane p = fit_marker_plane(scene.quad, scene.image, scene.cloud);
    ASSERT_TRUE(own.ok && p.ok);
    EXPECT_GT(angle_to_wall(own), 8) << seed;
    EXPECT_EQ(p.surround_scale, 3.0) << seed;
    EXPECT_LT(angle_to_wall(p), 1.0) << seed;
  }
}

TEST(MarkerPlane, SheetTurnedFromItsWallKeepsItsOwnPlane) {
  // 5 mm noise and a sheet turned 10 degrees about its middle: its points lie within the wall's
  // band and its mean on the wall, but its own plane's tilt is far beyond its uncertainty.
  const double slope = std::tan(10 * kDeg), row_z = std::tan(2 * kDeg);  // at 1 m
  const FewRowsOnWall scene(
      {-1.5 * row_z * slope, -0.5 * row_z * slope, 0.5 * row_z * slope, 1.5 * row_z * slope}, 0.005,
      4);
  const Plane p = fit_marker_plane(scene.quad, scene.image, scene.cloud);
  ASSERT_TRUE(p.ok);
  EXPECT_EQ(p.surround_scale, 1.0);
  EXPECT_NEAR(angle_to_wall(p), 10, 3);
}

TEST(MarkerPlane, SheetProudOfItsWallKeepsItsOwnPlaneWhenTheWallIsOffIt) {
  // A sheet 3 cm in front of the wall, 5 mm noise: parallel to the wall but not on it.
  const FewRowsOnWall scene({-0.03, -0.03, -0.03, -0.03}, 0.005, 3);
  const Plane p = fit_marker_plane(scene.quad, scene.image, scene.cloud);
  ASSERT_TRUE(p.ok);
  EXPECT_EQ(p.surround_scale, 1.0);
  EXPECT_NEAR(angle_to_wall(p), 0, 3);
}

TEST(MarkerPlane, PointsGatheredOnThreadsGiveTheOneThreadPlane) {
  // PlaneFitOptions::threads: a 0.05 deg image of a noisy wall, pixels holding one to three points
  // (single-point pixels take their point from the cloud, the others their mean range), a quad
  // 121 pixels wide whose 3x surround spans 363 x 363 pixels: three parts of at least 32k.
  const ImageGeometry g =
      geometry_for_bounds({-10 * kDeg, 10 * kDeg, -10 * kDeg, 10 * kDeg}, 0.05 * kDeg, 0.05 * kDeg);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.01);
  std::uniform_real_distribution<double> jitter(-0.45, 0.45);
  std::uniform_int_distribution<int> points_in(0, 3);
  PointCloud cloud;
  for (int r = 0; r < g.height; ++r)
    for (int c = 0; c < g.width; ++c)
      for (int k = points_in(rng); k > 0; --k) {
        const Vec3 ray = g.ray(c + jitter(rng), r + jitter(rng));
        const Vec3 p = ray * (-3.0 / kWallNormal.dot(ray) + noise(rng));
        cloud.push_back(p.x(), p.y(), p.z(), 100);
      }
  ProjectionOptions projection;
  projection.res_h_deg = projection.res_v_deg = 0.05;
  ProjectedImage image;
  SphericalProjector(projection).project(cloud, image);
  const std::vector<Vec2> quad = {Vec2(140, 140), Vec2(260, 140), Vec2(260, 260), Vec2(140, 260)};
  const Plane one = fit_marker_plane(quad, image, cloud);
  ASSERT_TRUE(one.ok);
  EXPECT_EQ(one.surround_scale, 3.0);
  EXPECT_GT(one.inliers, 60000u);
  for (int threads : {2, 3}) {
    PlaneFitOptions options;
    options.threads = threads;
    const Plane split = fit_marker_plane(quad, image, cloud, options);
    EXPECT_EQ(split.inliers, one.inliers) << threads;
    EXPECT_EQ(split.normal, one.normal) << threads;
    EXPECT_EQ(split.d, one.d) << threads;
    EXPECT_EQ(split.slope_variance(0), one.slope_variance(0)) << threads;
    EXPECT_EQ(split.slope_variance(1), one.slope_variance(1)) << threads;
    EXPECT_EQ(split.offset_variance, one.offset_variance) << threads;
  }
}

}  // namespace
}  // namespace iilfm
