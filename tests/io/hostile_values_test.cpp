// Values a broken driver writes: huge but finite coordinates and negative or zero intensities are
// kept exactly as written (the reader does not judge them; the pipeline must cope), non-finite
// ones skipped and counted; counts no file could hold are refused before anything is sized by
// them.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <limits>

#include "iilfm/io/cloud_io.hpp"
#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

TEST(HostileValues, HugeCoordinatesAndOddIntensitiesAreKeptNonFiniteSkipped) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  PointCloud written;
  written.push_back(1e30f, 2.0f, 3.0f, -5.0f);
  written.push_back(-FLT_MAX, FLT_MAX, 1.0f, 0.0f);
  written.push_back(1.0f, 1e-30f, -1e30f, -FLT_MAX);
  written.push_back(1.0f, inf, 1.0f, 1.0f);   // skipped: Inf coordinate
  written.push_back(1.0f, 2.0f, 3.0f, nan);   // skipped: NaN intensity
  written.push_back(-inf, 2.0f, 3.0f, 1.0f);  // skipped: -Inf coordinate
  testing::TempDir dir;
  for (PcdEncoding encoding :
       {PcdEncoding::kAscii, PcdEncoding::kBinary, PcdEncoding::kBinaryCompressed}) {
    const std::string path = dir.file("hostile.pcd");
    write_pcd(path, written, encoding);
    const LoadedCloud loaded = read_pcd(path);
    SCOPED_TRACE(static_cast<int>(encoding));
    EXPECT_EQ(loaded.stats.points_in_file, 6u);
    EXPECT_EQ(loaded.stats.non_finite, 3u);
    ASSERT_EQ(loaded.cloud.size(), 3u);
    EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1e30f, -FLT_MAX, 1.0f}));
    EXPECT_EQ(loaded.cloud.y, (std::vector<float>{2.0f, FLT_MAX, 1e-30f}));
    EXPECT_EQ(loaded.cloud.z, (std::vector<float>{3.0f, 1.0f, -1e30f}));
    EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{-5.0f, 0.0f, -FLT_MAX}));
  }
}

TEST(HostileValues, PlyVertexCountBeyondTheFileIsRefused) {
  testing::TempDir dir;
  for (const char* format : {"ascii", "binary_little_endian"}) {
    // 10^12 vertices of 12 bytes declared, 12 bytes present; and a count past 2^64.
    for (const char* count : {"1000000000000", "99999999999999999999999"}) {
      const std::string path = dir.file(std::string(format) + count + ".ply");
      std::string file = std::string("ply\nformat ") + format + " 1.0\nelement vertex " + count +
                         "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
      file += std::string(format) == "ascii" ? "1 2 3\n" : std::string(12, '\1');
      testing::write_bytes(path, file);
      SCOPED_TRACE(path);
      EXPECT_THROW(read_ply(path), InputError);
    }
  }
}

TEST(HostileValues, SinglePointCloudsReadInEveryFormat) {
  testing::TempDir dir;
  PointCloud one;
  one.push_back(4.0f, -1.0f, 0.5f, 7.0f);
  write_pcd(dir.file("one.pcd"), one, PcdEncoding::kBinaryCompressed);
  std::string kitti;
  for (float v : {4.0f, -1.0f, 0.5f, 7.0f}) testing::append_raw(kitti, v);
  testing::write_bytes(dir.file("one.bin"), kitti);
  testing::write_bytes(dir.file("one.xyz"), "4 -1 0.5 7\n");
  for (const char* name : {"one.pcd", "one.bin", "one.xyz"}) {
    const LoadedCloud loaded = read_cloud(dir.file(name));
    ASSERT_EQ(loaded.cloud.size(), 1u) << name;
    EXPECT_EQ(loaded.cloud.point(0), Vec3(4.0, -1.0, 0.5)) << name;
    EXPECT_EQ(loaded.cloud.intensity[0], 7.0f) << name;
  }
}

}  // namespace
}  // namespace iilfm::io
