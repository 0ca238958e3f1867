// The rosette never repeats: the covered part of the field of view grows with integration time.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "iilfm/sim/sim.hpp"
#include "plain_wall.hpp"

namespace iilfm::sim {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

Scene wall_filling_the_cone() { return testing::plain_wall(10, 40, 50); }

// Fraction of the cells of an azimuth/elevation grid of `res_deg` inside the cone that hold a
// point (cells cut by the cone's rim are left out).
double coverage(const PointCloud& cloud, double fov_deg, double res_deg) {
  const double half = fov_deg / 2;
  const int n = static_cast<int>(std::ceil(2 * half / res_deg));
  std::vector<char> hit(static_cast<std::size_t>(n) * n, 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const double azimuth = std::atan2(cloud.y[i], cloud.x[i]) * kRadToDeg;
    const double elevation = std::atan2(cloud.z[i], std::hypot(cloud.x[i], cloud.y[i])) * kRadToDeg;
    const int u = static_cast<int>(std::floor((half - azimuth) / res_deg));
    const int v = static_cast<int>(std::floor((half - elevation) / res_deg));
    if (u >= 0 && u < n && v >= 0 && v < n) hit[static_cast<std::size_t>(v) * n + u] = 1;
  }
  std::size_t inside = 0, covered = 0;
  for (int v = 0; v < n; ++v) {
    for (int u = 0; u < n; ++u) {
      const double az = half - (u + 0.5) * res_deg, el = half - (v + 0.5) * res_deg;
      if (std::hypot(az, el) > half - res_deg) continue;
      ++inside;
      covered += hit[static_cast<std::size_t>(v) * n + u];
    }
  }
  return static_cast<double>(covered) / inside;
}

TEST(Rosette, CoverageGrowsWithIntegratedFrames) {
  const Scene scene = wall_filling_the_cone();
  SimOptions o;
  o.range_sigma_m = 0;
  std::vector<double> fine, coarse;
  for (int frames : {1, 10, 20, 40, 100}) {
    o.frames = frames;
    const SimResult r = simulate(scene, mid40(), o);
    fine.push_back(coverage(r.cloud, 38.4, 0.05));
    coarse.push_back(coverage(r.cloud, 38.4, 0.1));
    std::cout << "[ measured ] Mid-40 " << frames << " frames (" << r.cloud.size()
              << " points): coverage of a 0.05 deg grid " << fine.back() << ", 0.1 deg grid "
              << coarse.back() << "\n";
  }
  for (std::size_t i = 1; i < 4; ++i) {
    EXPECT_GT(fine[i], fine[i - 1] * 1.5);
    EXPECT_GE(coarse[i], coarse[i - 1]);
  }
  EXPECT_GT(fine[4], fine[3] * 1.3);  // 10 s: still growing towards full coverage
  EXPECT_GT(fine[4], 0.85);
  EXPECT_GT(coarse[4], 0.999);
  // One second holds 100k points for about 463k cells of 0.05 deg: at most 22 % can be hit.
  // The rosette stays close to what uniformly random directions would give (1 - exp(-N/cells)).
  EXPECT_GT(fine[1], 0.15);
  EXPECT_LT(fine[1], 0.22);
  EXPECT_GT(fine[3], 0.50);  // 4 s
  EXPECT_LT(fine[3], 0.70);  // still holey
  EXPECT_GT(coarse[1], 0.40);
  EXPECT_LT(coarse[1], 0.60);
}

TEST(Rosette, PatternStaysInsideTheConeAndReachesItsRim) {
  const Scene scene = wall_filling_the_cone();
  SimOptions o;
  o.range_sigma_m = 0;
  const SimResult r = simulate(scene, mid40(), o);
  double widest = 0, nearest_axis = 90;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const Vec3 p = r.cloud.point(i);
    const double off_axis = std::acos(p.x() / p.norm()) * kRadToDeg;
    widest = std::max(widest, off_axis);
    nearest_axis = std::min(nearest_axis, off_axis);
  }
  EXPECT_LE(widest, 19.2 + 1e-4);
  EXPECT_GT(widest, 19.1);
  EXPECT_LT(nearest_axis, 0.1);  // every petal passes through the centre
}

// Its speed is measured in bench/ (Simulate/grid-40), not here.
TEST(Rosette, FortyFrameScanOfTheGridHasEveryPoint) {
  const SceneSetup setup = named_scene("grid");
  SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  o.frames = 40;
  const SimResult r = simulate(setup.scene, mid40(), o);
  EXPECT_EQ(r.cloud.size(), 400000u);
}

}  // namespace
}  // namespace iilfm::sim
