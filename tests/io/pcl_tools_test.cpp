// Interoperability with PCL's own tools (Debian pcl-tools): PCD files we write are loaded by
// pcl_pcd2ply (whose PLY we read back), and PCD files PCL writes in each encoding are read by us.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "iilfm/io/cloud_io.hpp"
#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

bool have_tool(const char* name) {
  return std::system((std::string("command -v ") + name + " >/dev/null 2>&1").c_str()) == 0;
}

#define SKIP_WITHOUT_PCL_TOOLS()                                               \
  if (!have_tool("pcl_pcd2ply") || !have_tool("pcl_convert_pcd_ascii_binary")) \
  GTEST_SKIP() << "PCL command-line tools absent: install Debian's pcl-tools " \
                  "(scripts/setup.sh)"

void run(const std::string& command) {
  ASSERT_EQ(std::system((command + " >/dev/null 2>&1").c_str()), 0) << command;
}

// Values that are not round in decimal, so any lossy conversion shows.
PointCloud sample_cloud() {
  PointCloud c;
  for (int i = 0; i < 500; ++i) {
    c.push_back(static_cast<float>(2 + std::sin(i * 0.37)), static_cast<float>(std::cos(i * 1.1)),
                static_cast<float>(i * 0.013 - 1), static_cast<float>((i * 37) % 255) + 0.25f);
    c.ring.push_back(static_cast<std::uint16_t>(i % 32));
    c.time.push_back(1600000000.0 + i * 1.3e-5);
  }
  return c;
}

void expect_equal_clouds(const PointCloud& a, const PointCloud& b, double time_tolerance) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
  EXPECT_EQ(a.intensity, b.intensity);
  EXPECT_EQ(a.ring, b.ring);
  ASSERT_EQ(a.time.size(), b.time.size());
  for (std::size_t i = 0; i < a.time.size(); ++i) EXPECT_NEAR(a.time[i], b.time[i], time_tolerance);
}

TEST(PclTools, Pcd2PlyLoadsOurPcdAndWeReadItsPly) {
  SKIP_WITHOUT_PCL_TOOLS();
  testing::TempDir dir;
  const PointCloud cloud = sample_cloud();
  const std::pair<PcdEncoding, const char*> encodings[] = {
      {PcdEncoding::kAscii, "ascii"},
      {PcdEncoding::kBinary, "binary"},
      {PcdEncoding::kBinaryCompressed, "compressed"}};
  for (const auto& [encoding, name] : encodings) {
    SCOPED_TRACE(name);
    const std::string pcd = dir.file(std::string(name) + ".pcd");
    const std::string ply = dir.file(std::string(name) + ".ply");
    write_pcd(pcd, cloud, encoding);
    run("pcl_pcd2ply -format 1 " + pcd + " " + ply);  // binary PLY: exact values
    expect_equal_clouds(read_ply(ply).cloud, cloud, 0);
  }
  const std::string pcd = dir.file("binary.pcd"), ascii_ply = dir.file("ascii.ply");
  run("pcl_pcd2ply -format 0 " + pcd + " " + ascii_ply);
  const PointCloud from_ascii = read_ply(ascii_ply).cloud;
  ASSERT_EQ(from_ascii.size(), cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_FLOAT_EQ(from_ascii.x[i], cloud.x[i]);
    EXPECT_FLOAT_EQ(from_ascii.intensity[i], cloud.intensity[i]);
  }
}

TEST(PclTools, WeReadPcdWrittenByPcl) {
  SKIP_WITHOUT_PCL_TOOLS();
  testing::TempDir dir;
  const PointCloud cloud = sample_cloud();
  const std::string ours = dir.file("ours.pcd");
  write_pcd(ours, cloud, PcdEncoding::kBinary);
  for (const int mode : {0, 1, 2}) {  // PCL's ascii, binary, binary_compressed
    SCOPED_TRACE(mode);
    const std::string theirs = dir.file("pcl_" + std::to_string(mode) + ".pcd");
    run("pcl_convert_pcd_ascii_binary " + ours + " " + theirs + " " + std::to_string(mode) + " 17");
    const LoadedCloud loaded = read_pcd(theirs);
    EXPECT_EQ(loaded.stats.points_in_file, cloud.size());
    expect_equal_clouds(loaded.cloud, cloud, mode == 0 ? 1e-6 : 0);
  }
}

}  // namespace
}  // namespace iilfm::io
