#include <gtest/gtest.h>

#include <limits>

#include "iilfm/io/cloud_io.hpp"
#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

using testing::append_raw;
using testing::write_bytes;

TEST(KittiReader, ReadsFloatQuadruples) {
  testing::TempDir dir;
  const std::string path = dir.file("000000.bin");
  std::string file;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const float v : {1.5f, -2.0f, 0.25f, 0.3f,  //
                        0.0f, 0.0f, 0.0f, 0.9f,    // zero: dropped
                        nan, 1.0f, 1.0f, 0.1f,     // non-finite: dropped
                        -40.0f, 12.5f, -1.75f, 0.0f}) {
    append_raw(file, v);
  }
  write_bytes(path, file);
  const LoadedCloud loaded = read_kitti_bin(path);
  EXPECT_EQ(loaded.stats.points_in_file, 4u);
  EXPECT_EQ(loaded.stats.valid_points, 2u);
  EXPECT_EQ(loaded.stats.zero, 1u);
  EXPECT_EQ(loaded.stats.non_finite, 1u);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1.5f, -40.0f}));
  EXPECT_EQ(loaded.cloud.y, (std::vector<float>{-2.0f, 12.5f}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{0.25f, -1.75f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{0.3f, 0.0f}));
  EXPECT_FALSE(loaded.cloud.has_ring());
  EXPECT_FALSE(loaded.cloud.has_time());
}

TEST(KittiReader, RejectsSizeNotMultipleOf16) {
  testing::TempDir dir;
  const std::string path = dir.file("broken.bin");
  write_bytes(path, std::string(33, '\0'));
  EXPECT_INPUT_ERROR(read_kitti_bin(path), path, "size 33 bytes is not a multiple of 16");
}

TEST(KittiReader, RejectsMissingAndEmptyFiles) {
  testing::TempDir dir;
  const std::string missing = dir.file("missing.bin");
  EXPECT_INPUT_ERROR(read_kitti_bin(missing), missing, "not found");
  const std::string empty = dir.file("empty.bin");
  write_bytes(empty, "");
  EXPECT_INPUT_ERROR(read_kitti_bin(empty), empty, "empty file");
}

}  // namespace
}  // namespace iilfm::io
