// A real Hesai Pandar64 scan (OpenCalib joint-calibration sample), binary_compressed as PCL
// writes it. Skipped when the shared data set is not on this machine.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "iilfm/io/cloud_io.hpp"

namespace iilfm::io {
namespace {

constexpr const char* kScan =
    "/work/shared/data/real/opencalib_jointcalib_pandar64/2022-01-18-15-25-03-449.pcd";

TEST(RealPcd, ReadsPandar64BinaryCompressed) {
  if (!std::filesystem::exists(kScan)) GTEST_SKIP() << kScan << " not available";
  const LoadedCloud loaded = read_pcd(kScan);
  const PointCloud& cloud = loaded.cloud;
  EXPECT_EQ(loaded.stats.points_in_file, 114535u);
  EXPECT_EQ(loaded.stats.valid_points + loaded.stats.non_finite + loaded.stats.zero, 114535u);
  EXPECT_GT(loaded.stats.valid_points, 100000u);
  ASSERT_EQ(cloud.size(), loaded.stats.valid_points);
  ASSERT_TRUE(cloud.has_ring());
  ASSERT_TRUE(cloud.has_time());

  const auto [ring_min, ring_max] = std::minmax_element(cloud.ring.begin(), cloud.ring.end());
  EXPECT_EQ(*ring_min, 0);
  EXPECT_EQ(*ring_max, 63);
  const auto [i_min, i_max] = std::minmax_element(cloud.intensity.begin(), cloud.intensity.end());
  EXPECT_GE(*i_min, 0.0f);
  EXPECT_LE(*i_max, 255.0f);
  EXPECT_GT(*i_max, 100.0f);
  const auto [t_min, t_max] = std::minmax_element(cloud.time.begin(), cloud.time.end());
  EXPECT_GT(*t_min, 1.6e9);  // absolute Unix time, January 2022
  EXPECT_NEAR(*t_max - *t_min, 0.1, 0.01);
  const auto [x_min, x_max] = std::minmax_element(cloud.x.begin(), cloud.x.end());
  EXPECT_LT(*x_min, -10.0f);
  EXPECT_GT(*x_max, 10.0f);
  EXPECT_LT(*x_max, 250.0f);  // Pandar64 range is 200 m
}

}  // namespace
}  // namespace iilfm::io
