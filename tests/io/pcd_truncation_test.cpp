// A small PCD cut at every byte boundary, in each encoding, is either refused with one InputError
// naming the file or (ascii, cut inside the last line) read as the same number of points; never a
// crash, never extra or made-up points.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "iilfm/io/cloud_io.hpp"
#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

// 12 points with intensity, ring and time: every column the writer emits.
PointCloud twelve_points() {
  PointCloud cloud;
  for (int i = 0; i < 12; ++i) {
    cloud.push_back(1.0f + 0.25f * i, -0.5f * i, 0.125f * (i - 6), static_cast<float>(10 * i));
    cloud.ring.push_back(static_cast<std::uint16_t>(i % 16));
    cloud.time.push_back(1e-4 * i);
  }
  return cloud;
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class PcdTruncation : public ::testing::TestWithParam<PcdEncoding> {};

TEST_P(PcdTruncation, EveryPrefixIsRefusedOrReadWithoutInventedPoints) {
  testing::TempDir dir;
  const std::string whole_path = dir.file("whole.pcd");
  const PointCloud original = twelve_points();
  write_pcd(whole_path, original, GetParam());
  const std::string bytes = bytes_of(whole_path);
  ASSERT_EQ(read_pcd(whole_path).cloud.size(), original.size());

  const std::string cut_path = dir.file("cut.pcd");
  std::size_t refused = 0, read = 0;
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    testing::write_bytes(cut_path, bytes.substr(0, length));
    try {
      const LoadedCloud loaded = read_pcd(cut_path);
      ++read;
      // Only ascii can lose bytes without losing a point: a cut inside the last value, or after
      // the last line's final digit. The points before the last are exact.
      EXPECT_EQ(GetParam(), PcdEncoding::kAscii) << "binary cut at " << length << " accepted";
      ASSERT_EQ(loaded.cloud.size(), original.size()) << "cut at " << length;
      for (std::size_t i = 0; i + 1 < original.size(); ++i) {
        EXPECT_EQ(loaded.cloud.x[i], original.x[i]) << "cut at " << length;
        EXPECT_EQ(loaded.cloud.intensity[i], original.intensity[i]) << "cut at " << length;
      }
    } catch (const InputError& error) {
      ++refused;
      const std::string message = error.what();
      EXPECT_NE(message.find(cut_path), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
  EXPECT_EQ(refused + read, bytes.size());
  // Everything up to the last line is refused in every encoding.
  EXPECT_GT(refused, bytes.size() - 40) << read << " prefixes read";
}

INSTANTIATE_TEST_SUITE_P(Encodings, PcdTruncation,
                         ::testing::Values(PcdEncoding::kAscii, PcdEncoding::kBinary,
                                           PcdEncoding::kBinaryCompressed));

}  // namespace
}  // namespace iilfm::io
