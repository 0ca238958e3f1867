// read_pcd against files written byte by byte from the format description, not by our writer.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "iilfm/io/cloud_io.hpp"
#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

using testing::append_raw;
using testing::pcd_header;
using testing::write_bytes;

TEST(PcdReader, ReadsHandWrittenAscii) {
  testing::TempDir dir;
  const std::string path = dir.file("hand.pcd");
  // An old-style header: VERSION .7, no COUNT and no VIEWPOINT, comments, tabs, CRLF and "nan".
  write_bytes(path,
              "# .PCD v.7 - Point Cloud Data file format\n"
              "VERSION .7\n"
              "FIELDS x y z intensity ring timestamp # Hesai-like\r\n"
              "SIZE 4 4 4 4 2 8\n"
              "TYPE F F F F U F\n"
              "WIDTH 5\n"
              "HEIGHT 1\n"
              "POINTS 5\n"
              "DATA ascii\n"
              "1.5 -2.25 3 12 7 100.125\n"
              "nan 1 1 5 0 100.2\r\n"
              "0 0 0 9 1 100.3\n"
              "\n"
              "+4e1\t5.5e-1  -6 255 63 100.4\n"
              "1 2 3 -nan 2 100.5");
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.points_in_file, 5u);
  EXPECT_EQ(loaded.stats.valid_points, 2u);
  EXPECT_EQ(loaded.stats.non_finite, 2u);
  EXPECT_EQ(loaded.stats.zero, 1u);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1.5f, 40.0f}));
  EXPECT_EQ(loaded.cloud.y, (std::vector<float>{-2.25f, 0.55f}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{3.0f, -6.0f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{12.0f, 255.0f}));
  EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{7, 63}));
  EXPECT_EQ(loaded.cloud.time, (std::vector<double>{100.125, 100.4}));
}

TEST(PcdReader, AsciiWithoutIntensityKeepsPointsWithZeroIntensity) {
  testing::TempDir dir;
  const std::string path = dir.file("xyz.pcd");
  write_bytes(path, pcd_header("x y z", "4 4 4", "F F F", "1 1 1", 2, "ascii") + "1 2 3\n4 5 6\n");
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.valid_points, 2u);
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{0.0f, 0.0f}));
  EXPECT_FALSE(loaded.cloud.has_ring());
  EXPECT_FALSE(loaded.cloud.has_time());
}

TEST(PcdReader, PrefersIntensityThenReflectivityThenI) {
  testing::TempDir dir;
  const std::string all = dir.file("all.pcd");
  write_bytes(all, pcd_header("i x reflectivity y intensity z", "4 4 4 4 4 4", "F F F F F F",
                              "1 1 1 1 1 1", 1, "ascii") +
                       "1 10 2 20 3 30\n");
  const LoadedCloud from_all = read_pcd(all);
  EXPECT_EQ(from_all.cloud.intensity, (std::vector<float>{3.0f}));
  EXPECT_EQ(from_all.cloud.x, (std::vector<float>{10.0f}));
  EXPECT_EQ(from_all.cloud.z, (std::vector<float>{30.0f}));

  const std::string two = dir.file("two.pcd");
  write_bytes(
      two, pcd_header("x y z i reflectivity", "4 4 4 4 4", "F F F F F", "1 1 1 1 1", 1, "ascii") +
               "1 2 3 4 5\n");
  EXPECT_EQ(read_pcd(two).cloud.intensity, (std::vector<float>{5.0f}));

  const std::string only_i = dir.file("i.pcd");
  write_bytes(only_i,
              pcd_header("x y z i", "4 4 4 4", "F F F F", "1 1 1 1", 1, "ascii") + "1 2 3 4\n");
  EXPECT_EQ(read_pcd(only_i).cloud.intensity, (std::vector<float>{4.0f}));
}

TEST(PcdReader, TakesAnOustersSignalOverItsReflectivity) {
  // The field layout of ouster-ros's native point type: the photon count is "signal" (what
  // "intensity" holds under the default type, and what the Ouster presets normalise).
  testing::TempDir dir;
  const std::string path = dir.file("native.pcd");
  write_bytes(path,
              pcd_header("x y z t range reflectivity signal ring near_ir", "4 4 4 4 4 1 2 2 2",
                         "F F F U U U U U U", "1 1 1 1 1 1 1 1 1", 1, "ascii") +
                  "1 2 3 50000 3741 12 850 31 40\n");
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{850.0f}));
  EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{31}));
}

TEST(PcdReader, MatchesFieldNamesAsThePlyAndRosReadersDo) {
  // In any letter case and with CloudCompare's "scalar_" prefix, as PLY files and PointCloud2
  // messages name them (they were matched in lower case only).
  testing::TempDir dir;
  const std::string path = dir.file("upper.pcd");
  write_bytes(path, pcd_header("X Y Z scalar_Intensity Ring", "4 4 4 4 2", "F F F F U", "1 1 1 1 1",
                               1, "ascii") +
                        "1 2 3 77 5\n");
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1.0f}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{3.0f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{77.0f}));
  EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{5}));
}

TEST(PcdReader, ReadsChannelAsRingAndTAsTime) {
  testing::TempDir dir;
  const std::string path = dir.file("ouster.pcd");
  write_bytes(path, pcd_header("x y z t reflectivity channel", "4 4 4 4 2 1", "F F F U U U",
                               "1 1 1 1 1 1", 1, "ascii") +
                        "1 2 3 50000 300 17\n");
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{17}));
  EXPECT_EQ(loaded.cloud.time, (std::vector<double>{50000.0}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{300.0f}));
}

TEST(PcdReader, ReadsHandBuiltBinaryWithMixedTypes) {
  testing::TempDir dir;
  const std::string path = dir.file("mixed.pcd");
  // x y z as float64, three bytes of padding, intensity as uint8, ring as int16, time as uint64
  // (e.g. nanoseconds), then an unknown float field with two elements.
  std::string file = pcd_header("x y z _ intensity ring time normal", "8 8 8 1 1 2 8 4",
                                "F F F U U I U F", "1 1 1 3 1 1 1 2", 3, "binary");
  const auto add_point = [&](double x, double y, double z, std::uint8_t intensity,
                             std::int16_t ring, std::uint64_t time) {
    append_raw(file, x);
    append_raw(file, y);
    append_raw(file, z);
    file.append("\xAA\xBB\xCC", 3);
    append_raw(file, intensity);
    append_raw(file, ring);
    append_raw(file, time);
    append_raw(file, 0.5f);
    append_raw(file, -0.5f);
  };
  add_point(1.25, -2.5, 1e6, 200, 31, 1000000000000ull);
  add_point(0.0, 0.0, 0.0, 1, 2, 3);  // dropped: zero
  add_point(-7.0, 8.0, 9.125, 255, -4, 42);
  file += "trailing bytes are ignored";
  write_bytes(path, file);

  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.points_in_file, 3u);
  EXPECT_EQ(loaded.stats.valid_points, 2u);
  EXPECT_EQ(loaded.stats.zero, 1u);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1.25f, -7.0f}));
  EXPECT_EQ(loaded.cloud.y, (std::vector<float>{-2.5f, 8.0f}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{1e6f, 9.125f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{200.0f, 255.0f}));
  EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{31, 0}));  // negative ring clamps to 0
  EXPECT_EQ(loaded.cloud.time, (std::vector<double>{1e12, 42.0}));
}

TEST(PcdReader, TakesElementZeroOfMultiElementFields) {
  testing::TempDir dir;
  const std::string path = dir.file("counts.pcd");
  // Integer coordinates, a two-element intensity and an unsigned 32-bit ring.
  std::string file =
      pcd_header("x y z intensity ring", "4 2 1 2 4", "I I I U U", "1 1 1 2 1", 2, "binary");
  for (int p = 0; p < 2; ++p) {
    append_raw<std::int32_t>(file, -100000 * (p + 1));
    append_raw<std::int16_t>(file, static_cast<std::int16_t>(-300 + p));
    append_raw<std::int8_t>(file, static_cast<std::int8_t>(-128 + p));
    append_raw<std::uint16_t>(file, static_cast<std::uint16_t>(60000 + p));
    append_raw<std::uint16_t>(file, 9);  // element 1: skipped
    append_raw<std::uint32_t>(file, p == 0 ? 5u : 70000u);
  }
  write_bytes(path, file);
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{-100000.0f, -200000.0f}));
  EXPECT_EQ(loaded.cloud.y, (std::vector<float>{-300.0f, -299.0f}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{-128.0f, -127.0f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{60000.0f, 60001.0f}));
  EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{5, 65535}));  // saturates
}

TEST(PcdReader, CountsNonFiniteBinaryPoints) {
  testing::TempDir dir;
  const std::string path = dir.file("nan.pcd");
  std::string file = pcd_header("x y z intensity", "4 4 4 8", "F F F F", "1 1 1 1", 4, "binary");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const auto add = [&](float x, float y, float z, double i) {
    append_raw(file, x);
    append_raw(file, y);
    append_raw(file, z);
    append_raw(file, i);
  };
  add(1, 2, 3, 4);
  add(1, nan, 3, 4);
  add(1, 2, 3, 1e300);  // beyond float range: infinite intensity
  add(0, 0, 0, 4);
  write_bytes(path, file);
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.points_in_file, 4u);
  EXPECT_EQ(loaded.stats.valid_points, 1u);
  EXPECT_EQ(loaded.stats.non_finite, 2u);
  EXPECT_EQ(loaded.stats.zero, 1u);
}

TEST(PcdReader, ReadsHandBuiltBinaryCompressed) {
  testing::TempDir dir;
  const std::string path = dir.file("packed.pcd");
  // Field-major columns: all x, then all y, all z, all ring (uint16), all intensity (uint8).
  std::string columns;
  for (float x : {1.0f, 2.0f, 3.0f}) append_raw(columns, x);
  for (float y : {-1.0f, -2.0f, -3.0f}) append_raw(columns, y);
  for (float z : {0.5f, 0.0f, 0.25f}) append_raw(columns, z);
  for (std::uint16_t ring : {4, 5, 6}) append_raw(columns, ring);
  for (std::uint8_t intensity : {10, 20, 30}) append_raw(columns, intensity);
  const std::string packed = testing::lzf_literals(columns);
  std::string file = pcd_header("x y z ring intensity", "4 4 4 2 1", "F F F U U", "1 1 1 1 1", 3,
                                "binary_compressed");
  append_raw(file, static_cast<std::uint32_t>(packed.size()));
  append_raw(file, static_cast<std::uint32_t>(columns.size()));
  file += packed;
  write_bytes(path, file);

  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.valid_points, 3u);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1, 2, 3}));
  EXPECT_EQ(loaded.cloud.y, (std::vector<float>{-1, -2, -3}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{0.5f, 0, 0.25f}));
  EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{4, 5, 6}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{10, 20, 30}));
}

TEST(PcdReader, ReadsOrganizedCloudWithoutPointsLine) {
  testing::TempDir dir;
  const std::string path = dir.file("organized.pcd");
  write_bytes(path,
              "VERSION .6\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nDATA ascii\n"
              "1 1 1\n2 2 2\n3 3 3\n4 4 4\n");
  const LoadedCloud loaded = read_pcd(path);
  EXPECT_EQ(loaded.stats.points_in_file, 4u);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1, 2, 3, 4}));
}

}  // namespace
}  // namespace iilfm::io
