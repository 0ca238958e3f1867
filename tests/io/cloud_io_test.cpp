// read_cloud chooses the reader by extension, case-insensitively.
#include "iilfm/io/cloud_io.hpp"

#include <gtest/gtest.h>

#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

TEST(ReadCloud, DispatchesOnExtension) {
  testing::TempDir dir;
  PointCloud cloud;
  cloud.push_back(1, 2, 3, 4);
  const std::string pcd = dir.file("scan.PCD");
  write_pcd(pcd, cloud);
  EXPECT_EQ(read_cloud(pcd).cloud.x, (std::vector<float>{1}));

  const std::string bin = dir.file("scan.Bin");
  std::string record;
  for (const float v : {5.0f, 6.0f, 7.0f, 8.0f}) testing::append_raw(record, v);
  testing::write_bytes(bin, record);
  EXPECT_EQ(read_cloud(bin).cloud.intensity, (std::vector<float>{8}));
}

TEST(ReadCloud, RejectsOtherExtensions) {
  testing::TempDir dir;
  const std::string las = dir.file("scan.las");
  testing::write_bytes(las, "LASF");
  EXPECT_INPUT_ERROR(read_cloud(las),
                     las +
                         ": unsupported cloud format '.las' (supported: .pcd, .bin, .ply, .txt, "
                         ".xyz, .xyzi, .csv)",
                     "unsupported");
  const std::string bare = dir.file("scan");
  EXPECT_INPUT_ERROR(read_cloud(bare), bare, "unsupported cloud format (no extension)");
}

}  // namespace
}  // namespace iilfm::io
