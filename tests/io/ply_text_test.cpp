// PLY (ascii and both binary byte orders) and plain-text XYZI files, and folders of them as frame
// sequences.
#include <gtest/gtest.h>

#include "iilfm/io/cloud_io.hpp"
#include "iilfm/io/frame_source.hpp"
#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

template <typename T>
void append_big(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  for (int i = sizeof(T) - 1; i >= 0; --i) out.push_back(bytes[i]);
}

const std::string kPlyProperties =
    "property double x\nproperty double y\nproperty double z\n"
    "property uchar red\nproperty float scalar_Intensity\nproperty ushort ring\n";

// Three vertices, one at the origin (dropped); a face element after them that must be ignored.
std::string binary_ply(bool big_endian) {
  std::string out = std::string("ply\nformat ") +
                    (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment made by a test\nelement vertex 3\n" + kPlyProperties +
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const double xyz[3][3] = {{1.5, -2.25, 0.125}, {0, 0, 0}, {3.0, 4.0, 5.0}};
  const float intensity[3] = {17.5f, 1.0f, 250.0f};
  for (int i = 0; i < 3; ++i) {
    for (double v : xyz[i]) big_endian ? append_big(out, v) : testing::append_raw(out, v);
    out.push_back(static_cast<char>(200));  // red: not a column we read
    big_endian ? append_big(out, intensity[i]) : testing::append_raw(out, intensity[i]);
    const std::uint16_t ring = static_cast<std::uint16_t>(7 + i);
    big_endian ? append_big(out, ring) : testing::append_raw(out, ring);
  }
  out.push_back(3);
  for (int i = 0; i < 3; ++i) big_endian ? append_big(out, i) : testing::append_raw(out, i);
  return out;
}

void expect_two_points(const LoadedCloud& loaded) {
  EXPECT_EQ(loaded.stats.points_in_file, 3u);
  EXPECT_EQ(loaded.stats.zero, 1u);
  ASSERT_EQ(loaded.cloud.size(), 2u);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1.5f, 3.0f}));
  EXPECT_EQ(loaded.cloud.y, (std::vector<float>{-2.25f, 4.0f}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{0.125f, 5.0f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{17.5f, 250.0f}));
  EXPECT_EQ(loaded.cloud.ring, (std::vector<std::uint16_t>{7, 9}));
}

TEST(Ply, BinaryBothByteOrders) {
  testing::TempDir dir;
  for (const bool big : {false, true}) {
    const std::string path = dir.file(big ? "big.ply" : "little.ply");
    testing::write_bytes(path, binary_ply(big));
    SCOPED_TRACE(path);
    expect_two_points(read_cloud(path));
  }
}

TEST(Ply, Ascii) {
  testing::TempDir dir;
  const std::string path = dir.file("scan.PLY");
  testing::write_bytes(path, "ply\r\nformat ascii 1.0\nelement vertex 3\n" + kPlyProperties +
                                 "end_header\n1.5 -2.25 0.125 200 17.5 7\n0 0 0 1 1 8\n"
                                 "3 4 5 200 250 9\n");
  expect_two_points(read_cloud(path));
}

TEST(Ply, ElementsBeforeTheVerticesAreSkipped) {
  testing::TempDir dir;
  const std::string path = dir.file("scan.ply");
  std::string body;
  body.push_back(2);  // a list of two int8
  body.push_back(1);
  body.push_back(2);
  for (const float v : {1.0f, 2.0f, 3.0f, 9.0f}) testing::append_raw(body, v);
  testing::write_bytes(path,
                       "ply\nformat binary_little_endian 1.0\nelement camera 1\nproperty list "
                       "uchar char stuff\nelement vertex 1\nproperty float x\nproperty float y\n"
                       "property float z\nproperty float reflectivity\nend_header\n" +
                           body);
  const LoadedCloud loaded = read_cloud(path);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1.0f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{9.0f}));
}

TEST(Ply, Errors) {
  testing::TempDir dir;
  const std::string path = dir.file("bad.ply");
  testing::write_bytes(path,
                       "ply\nformat binary_little_endian 1.0\nelement vertex 1000\n"
                       "property float x\nproperty float y\nproperty float z\nend_header\n"
                       "abcd");
  EXPECT_INPUT_ERROR(read_cloud(path), path, "truncated PLY data");
  testing::write_bytes(path,
                       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\n"
                       "end_header\n1\n");
  EXPECT_INPUT_ERROR(read_cloud(path), path, "no x, y, z");
  testing::write_bytes(path,
                       "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                       "property float y\nproperty float z\nend_header\n1 2 3\n1 2 oops\n");
  EXPECT_INPUT_ERROR(read_cloud(path), path, "line 9: 'oops' is not a number");
  testing::write_bytes(path, "ply\nformat ascii 1.0\nelement vertex 1\n");
  EXPECT_INPUT_ERROR(read_cloud(path), path, "no end_header");
  testing::write_bytes(path, "PCD\n");
  EXPECT_INPUT_ERROR(read_cloud(path), path, "not a PLY file");
}

TEST(XyzText, BlanksCommasCommentsAndAHeaderLine) {
  testing::TempDir dir;
  const std::string path = dir.file("scan.xyzi");
  testing::write_bytes(path,
                       "x,y,z,intensity\n# exported\n1.5, -2, 3, 40\n\n0 0 0 5  # no return\n"
                       "nan 1 2 3\r\n4\t5\t6\t7\n");
  const LoadedCloud loaded = read_cloud(path);
  EXPECT_EQ(loaded.stats.points_in_file, 4u);
  EXPECT_EQ(loaded.stats.zero, 1u);
  EXPECT_EQ(loaded.stats.non_finite, 1u);
  EXPECT_EQ(loaded.cloud.x, (std::vector<float>{1.5f, 4.0f}));
  EXPECT_EQ(loaded.cloud.z, (std::vector<float>{3.0f, 6.0f}));
  EXPECT_EQ(loaded.cloud.intensity, (std::vector<float>{40.0f, 7.0f}));

  const std::string xyz = dir.file("scan.xyz");
  testing::write_bytes(xyz, "1 2 3\n4 5 6\n");
  EXPECT_EQ(read_cloud(xyz).cloud.intensity, (std::vector<float>{0.0f, 0.0f}));
}

TEST(XyzText, Errors) {
  testing::TempDir dir;
  const std::string path = dir.file("scan.txt");
  testing::write_bytes(path, "1 2 3 4\n1 2 3\n");
  EXPECT_INPUT_ERROR(read_cloud(path), path, "line 2 has 3 values, the first point line has 4");
  testing::write_bytes(path, "1 2 3 4\n1 2 x 4\n");
  EXPECT_INPUT_ERROR(read_cloud(path), path, "line 2: not a number");
  testing::write_bytes(path, "1 2\n");
  EXPECT_INPUT_ERROR(read_cloud(path), path, "line 1 has 2 values");
}

TEST(FolderFrames, EveryCloudFileInNameOrderWithStampsFromNames) {
  testing::TempDir dir;
  PointCloud cloud;
  cloud.push_back(1, 2, 3, 4);
  write_pcd(dir.file("1600000000.200000.pcd"), cloud);
  write_pcd(dir.file("1600000000.100000.pcd"), cloud);
  testing::write_bytes(dir.file("1600000000300000000.xyz"), "5 6 7 8\n");
  testing::write_bytes(dir.file("notes.md"), "not a cloud\n");
  const auto source = open_frame_source(dir.file("."), "");
  EXPECT_EQ(source->total(), 3u);
  Frame frame;
  const double stamps[] = {1600000000.1, 1600000000.2, 1600000000.3};
  for (std::size_t i = 0; i < 3; ++i) {
    ASSERT_TRUE(source->next(frame));
    EXPECT_EQ(frame.index, i);
    EXPECT_NEAR(frame.stamp_s, stamps[i], 1e-6);
    EXPECT_EQ(frame.loaded.cloud.size(), 1u);
  }
  EXPECT_EQ(frame.loaded.cloud.x[0], 5.0f);
  EXPECT_FALSE(source->next(frame));
}

}  // namespace
}  // namespace iilfm::io
