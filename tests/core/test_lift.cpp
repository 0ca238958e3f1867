#include <gtest/gtest.h>

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
