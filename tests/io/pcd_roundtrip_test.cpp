// write_pcd then read_pcd must give back every value bit for bit, in each encoding.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <tuple>

#include "iilfm/io/cloud_io.hpp"
#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

PointCloud random_cloud(std::size_t n, bool with_ring, bool with_time) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coordinate(-120.0f, 120.0f);
  std::uniform_real_distribution<float> reflectance(0.0f, 255.0f);
  PointCloud cloud;
  for (std::size_t i = 0; i < n; ++i) {
    cloud.push_back(coordinate(rng), coordinate(rng), coordinate(rng), reflectance(rng));
    if (with_ring) cloud.ring.push_back(static_cast<std::uint16_t>(i % 64));
    if (with_time) cloud.time.push_back(1642490703.449 + 1e-6 * static_cast<double>(i) / 3.0);
  }
  // Values that need all nine significant digits or are extreme still round-trip.
  cloud.x[0] = 0.1f;
  cloud.y[0] = 1.0e-30f;
  cloud.z[0] = -3.4e38f;
  cloud.intensity[0] = 16777217.0f;
  return cloud;
}

class PcdRoundTrip : public ::testing::TestWithParam<std::tuple<PcdEncoding, bool, bool>> {};

TEST_P(PcdRoundTrip, ReadsBackExactly) {
  const auto [encoding, with_ring, with_time] = GetParam();
  testing::TempDir dir;
  const std::string path = dir.file("cloud.pcd");
  const PointCloud written = random_cloud(5000, with_ring, with_time);
  write_pcd(path, written, encoding);

  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.points_in_file, 5000u);
  EXPECT_EQ(loaded.stats.valid_points, 5000u);
  EXPECT_EQ(loaded.stats.non_finite, 0u);
  EXPECT_EQ(loaded.stats.zero, 0u);
  EXPECT_EQ(loaded.cloud.x, written.x);
  EXPECT_EQ(loaded.cloud.y, written.y);
  EXPECT_EQ(loaded.cloud.z, written.z);
  EXPECT_EQ(loaded.cloud.intensity, written.intensity);
  EXPECT_EQ(loaded.cloud.ring, written.ring);
  EXPECT_EQ(loaded.cloud.time, written.time);
}

TEST_P(PcdRoundTrip, EmptyCloud) {
  const auto [encoding, with_ring, with_time] = GetParam();
  testing::TempDir dir;
  const std::string path = dir.file("empty.pcd");
  write_pcd(path, PointCloud{}, encoding);
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.points_in_file, 0u);
  EXPECT_EQ(loaded.stats.valid_points, 0u);
  EXPECT_TRUE(loaded.cloud.empty());
}

TEST_P(PcdRoundTrip, SkipsNonFiniteAndZeroPoints) {
  const auto [encoding, with_ring, with_time] = GetParam();
  testing::TempDir dir;
  const std::string path = dir.file("holes.pcd");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  PointCloud cloud;
  cloud.push_back(1, 2, 3, 10);     // kept
  cloud.push_back(nan, 2, 3, 10);   // non-finite x
  cloud.push_back(0, 0, 0, 10);     // zero
  cloud.push_back(4, -inf, 6, 10);  // non-finite y
  cloud.push_back(7, 8, 9, nan);    // non-finite intensity
  cloud.push_back(0, 0, 0.5f, 11);  // kept: only one coordinate needs to be non-zero
  cloud.push_back(-0.0f, 0, 0, 1);  // zero
  for (std::uint16_t i = 0; i < 7; ++i) {
    if (with_ring) cloud.ring.push_back(i);
    if (with_time) cloud.time.push_back(0.25 * i);
  }
  write_pcd(path, cloud, encoding);

  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.points_in_file, 7u);
  EXPECT_EQ(loaded.stats.valid_points, 2u);
  EXPECT_EQ(loaded.stats.non_finite, 3u);
  EXPECT_EQ(loaded.stats.zero, 2u);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1, 0}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{3, 0.5f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{10, 11}));
  if (with_ring) {
    EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{0, 5}));
  }
  if (with_time) {
    EXPECT_EQ(loaded.cloud.time, (std::vector<double>{0.0, 1.25}));
  }
}

std::string encoding_case_name(
    const ::testing::TestParamInfo<std::tuple<PcdEncoding, bool, bool>>& info) {
  static const char* const kNames[] = {"Ascii", "Binary", "BinaryCompressed"};
  return std::string(kNames[static_cast<int>(std::get<0>(info.param))]) +
         (std::get<1>(info.param) ? "_Ring" : "") + (std::get<2>(info.param) ? "_Time" : "");
}

INSTANTIATE_TEST_SUITE_P(AllEncodings, PcdRoundTrip,
                         ::testing::Combine(::testing::Values(PcdEncoding::kAscii,
                                                              PcdEncoding::kBinary,
                                                              PcdEncoding::kBinaryCompressed),
                                            ::testing::Bool(), ::testing::Bool()),
                         encoding_case_name);

TEST(PcdWriter, WritesTheDocumentedHeader) {
  testing::TempDir dir;
  const std::string path = dir.file("header.pcd");
  PointCloud cloud;
  cloud.push_back(1, 2, 3, 4);
  cloud.ring = {5};
  cloud.time = {0.5};
  write_pcd(path, cloud, PcdEncoding::kAscii);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text,
            "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
            "FIELDS x y z intensity ring time\nSIZE 4 4 4 4 2 8\nTYPE F F F F U F\n"
            "COUNT 1 1 1 1 1 1\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\n"
            "DATA ascii\n1 2 3 4 5 0.5\n");
}

TEST(PcdWriter, BinaryCompressedIsSmallerForRepetitiveClouds) {
  testing::TempDir dir;
  PointCloud cloud;
  for (int i = 0; i < 10000; ++i) cloud.push_back(1.0f, 2.0f, static_cast<float>(i % 10), 7.0f);
  write_pcd(dir.file("plain.pcd"), cloud, PcdEncoding::kBinary);
  write_pcd(dir.file("packed.pcd"), cloud, PcdEncoding::kBinaryCompressed);
  EXPECT_LT(std::filesystem::file_size(dir.file("packed.pcd")) * 20,
            std::filesystem::file_size(dir.file("plain.pcd")));
}

TEST(PcdWriter, ReportsUnwritablePath) {
  testing::TempDir dir;
  const std::string path = dir.file("no_such_dir/cloud.pcd");
  PointCloud cloud;
  cloud.push_back(1, 2, 3, 4);
  EXPECT_INPUT_ERROR(write_pcd(path, cloud), path, "cannot create");
}

TEST(PcdWriter, RejectsColumnsOfDifferentLength) {
  testing::TempDir dir;
  const std::string path = dir.file("bad.pcd");
  PointCloud cloud;
  cloud.push_back(1, 2, 3, 4);
  cloud.push_back(5, 6, 7, 8);
  cloud.ring = {1};
  EXPECT_INPUT_ERROR(write_pcd(path, cloud), path, "differ in length");
}

}  // namespace
}  // namespace iilfm::io
