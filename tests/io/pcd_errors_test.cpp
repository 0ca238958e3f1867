// Every malformed PCD must end in one InputError naming the file and the problem: no crash, no
// allocation sized by an unchecked header value.
#include <gtest/gtest.h>

#include "iilfm/io/cloud_io.hpp"
#include "io_test_support.hpp"

namespace iilfm::io {
namespace {

using testing::append_raw;
using testing::pcd_header;
using testing::write_bytes;

class PcdErrors : public ::testing::Test {
 protected:
  // Writes `bytes` to a fresh file and returns its path.
  std::string file_with(const std::string& bytes) {
    const std::string path = dir_.file("bad" + std::to_string(files_++) + ".pcd");
    write_bytes(path, bytes);
    return path;
  }
  std::string xyz_header(std::uint64_t points, const std::string& data) {
    return pcd_header("x y z", "4 4 4", "F F F", "1 1 1", points, data);
  }
  std::string compressed_file(std::uint64_t points, std::uint32_t compressed,
                              std::uint32_t uncompressed, const std::string& payload) {
    std::string file = xyz_header(points, "binary_compressed");
    append_raw(file, compressed);
    append_raw(file, uncompressed);
    return file + payload;
  }

  testing::TempDir dir_;
  int files_ = 0;
};

TEST_F(PcdErrors, MissingFile) {
  const std::string path = dir_.file("absent.pcd");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "not found");
}

TEST_F(PcdErrors, EmptyFile) {
  const std::string path = file_with("");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "empty file");
}

TEST_F(PcdErrors, Directory) {
  const std::string path = dir_.file("");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "not a regular file");
}

TEST_F(PcdErrors, NotAPcdFile) {
  const std::string path = file_with(std::string("\x01\x02\x00\xff garbage", 12));
  EXPECT_INPUT_ERROR(read_pcd(path), path, "no DATA line");
}

TEST_F(PcdErrors, MissingFields) {
  const std::string path =
      file_with("VERSION 0.7\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "missing FIELDS");
}

TEST_F(PcdErrors, MissingSizeAndType) {
  const std::string no_size = file_with("FIELDS x y z\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n");
  EXPECT_INPUT_ERROR(read_pcd(no_size), no_size, "missing SIZE");
  const std::string no_type = file_with("FIELDS x y z\nSIZE 4 4 4\nPOINTS 1\nDATA ascii\n1 2 3\n");
  EXPECT_INPUT_ERROR(read_pcd(no_type), no_type, "missing TYPE");
}

TEST_F(PcdErrors, MissingCoordinate) {
  const std::string path =
      file_with(pcd_header("x y intensity", "4 4 4", "F F F", "1 1 1", 1, "ascii") + "1 2 3\n");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "no 'z' field");
}

TEST_F(PcdErrors, MismatchedListLengths) {
  const std::string size = file_with(pcd_header("x y z", "4 4", "F F F", "1 1 1", 1, "ascii"));
  EXPECT_INPUT_ERROR(read_pcd(size), size, "SIZE lists 2 values but FIELDS names 3");
  const std::string type = file_with(pcd_header("x y z", "4 4 4", "F F F F", "1 1 1", 1, "ascii"));
  EXPECT_INPUT_ERROR(read_pcd(type), type, "TYPE lists 4 values");
  const std::string count = file_with(pcd_header("x y z", "4 4 4", "F F F", "1", 1, "ascii"));
  EXPECT_INPUT_ERROR(read_pcd(count), count, "COUNT lists 1 values");
}

TEST_F(PcdErrors, UnknownTypeOrSize) {
  const std::string type = file_with(pcd_header("x y z", "4 4 4", "F Q F", "1 1 1", 1, "ascii"));
  EXPECT_INPUT_ERROR(read_pcd(type), type, "unsupported TYPE Q with SIZE 4 for field 'y'");
  const std::string half = file_with(pcd_header("x y z", "4 4 2", "F F F", "1 1 1", 1, "ascii"));
  EXPECT_INPUT_ERROR(read_pcd(half), half, "unsupported TYPE F with SIZE 2");
  const std::string odd = file_with(pcd_header("x y z", "4 4 3", "F F U", "1 1 1", 1, "ascii"));
  EXPECT_INPUT_ERROR(read_pcd(odd), odd, "SIZE 3");
  const std::string word = file_with(pcd_header("x y z", "4 four 4", "F F F", "1 1 1", 1, "ascii"));
  EXPECT_INPUT_ERROR(read_pcd(word), word, "SIZE of field 'y' is not a number");
}

TEST_F(PcdErrors, BadCount) {
  const std::string zero = file_with(pcd_header("x y z", "4 4 4", "F F F", "1 0 1", 1, "ascii"));
  EXPECT_INPUT_ERROR(read_pcd(zero), zero, "COUNT of field 'y'");
  const std::string huge =
      file_with(pcd_header("x y z", "4 4 4", "F F F", "1 1 99999999999999", 1, "binary"));
  EXPECT_INPUT_ERROR(read_pcd(huge), huge, "COUNT of field 'z'");
}

TEST_F(PcdErrors, PointsDisagreeWithWidthTimesHeight) {
  const std::string path = file_with(
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 10\nHEIGHT 9\nPOINTS 100\nDATA binary\n");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "POINTS 100 does not match WIDTH*HEIGHT 10*9 = 90");
  const std::string overflow = file_with(
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 18446744073709551615\nHEIGHT 2\nDATA binary\n");
  EXPECT_INPUT_ERROR(read_pcd(overflow), overflow, "overflows");
  const std::string neither = file_with("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nDATA binary\n");
  EXPECT_INPUT_ERROR(read_pcd(neither), neither, "missing POINTS and WIDTH");
  const std::string negative =
      file_with("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH -3\nDATA binary\n");
  EXPECT_INPUT_ERROR(read_pcd(negative), negative, "WIDTH is not a non-negative integer");
}

TEST_F(PcdErrors, UnknownDataEncoding) {
  const std::string path = file_with(xyz_header(1, "binary_lz4"));
  EXPECT_INPUT_ERROR(read_pcd(path), path, "unknown DATA encoding 'binary_lz4'");
}

TEST_F(PcdErrors, TruncatedBinary) {
  std::string file = xyz_header(100, "binary");
  file.append(1000, '\0');  // 100 points of 12 bytes need 1200
  const std::string path = file_with(file);
  EXPECT_INPUT_ERROR(read_pcd(path), path,
                     "truncated binary data: expected 1200 bytes, found 1000");
}

TEST_F(PcdErrors, BinarySizesThatOverflowOrExceedTheFile) {
  // 2^62 points of 12 bytes overflow 64 bits; 10^15 points fit the arithmetic but not the file.
  const std::string overflow = file_with(xyz_header(std::uint64_t{1} << 62, "binary") + "abc");
  EXPECT_INPUT_ERROR(read_pcd(overflow), overflow, "overflows");
  const std::string huge = file_with(xyz_header(1000000000000000ull, "binary") + "abc");
  EXPECT_INPUT_ERROR(read_pcd(huge), huge, "truncated binary data: expected 12000000000000000");
}

TEST_F(PcdErrors, AsciiWithFewerLinesThanPoints) {
  const std::string path = file_with(xyz_header(4, "ascii") + "1 2 3\n4 5 6\n\n");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "truncated ascii data: expected 4 points, found 2");
  // A huge POINTS must not reserve memory for it.
  const std::string huge = file_with(xyz_header(1000000000000000ull, "ascii") + "1 2 3\n");
  EXPECT_INPUT_ERROR(read_pcd(huge), huge, "expected 1000000000000000 points, found 1");
}

TEST_F(PcdErrors, AsciiCountsBeyondTheData) {
  // 3 * 2^24 values per point declared in a file of a few hundred bytes: refused before sizing
  // anything by it.
  const std::string path = file_with(
      pcd_header("x y z", "4 4 4", "F F F", "16777216 16777216 16777216", 1, "ascii") + "1 2 3\n");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "truncated ascii data: a point has 50331648 values");
  const std::string no_points =
      file_with(pcd_header("x y z", "4 4 4", "F F F", "16777216 16777216 16777216", 0, "ascii"));
  EXPECT_EQ(read_pcd(no_points).stats.points_in_file, 0u);
}

TEST_F(PcdErrors, AsciiLineWithWrongValueCount) {
  const std::string few = file_with(xyz_header(2, "ascii") + "1 2 3\n4 5\n");
  EXPECT_INPUT_ERROR(read_pcd(few), few, "ascii data line 13 has 2 values, expected 3");
  const std::string many = file_with(xyz_header(1, "ascii") + "1 2 3 4\n");
  EXPECT_INPUT_ERROR(read_pcd(many), many, "has 4 values, expected 3");
}

TEST_F(PcdErrors, AsciiNonNumericToken) {
  const std::string path = file_with(xyz_header(2, "ascii") + "1 2 3\n4 five 6\n");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "ascii data line 13 value 2 is not a number: 'five'");
  const std::string partial = file_with(xyz_header(1, "ascii") + "1 2.5x 3\n");
  EXPECT_INPUT_ERROR(read_pcd(partial), partial, "is not a number: '2.5x'");
}

TEST_F(PcdErrors, CompressedWithoutSizeHeader) {
  const std::string path = file_with(xyz_header(1, "binary_compressed") + "abc");
  EXPECT_INPUT_ERROR(read_pcd(path), path, "truncated binary_compressed data");
}

TEST_F(PcdErrors, CompressedDataShorterThanDeclared) {
  const std::string path = file_with(compressed_file(1, 500, 12, std::string(20, '\0')));
  EXPECT_INPUT_ERROR(read_pcd(path), path,
                     "truncated compressed data: expected 500 bytes, found 20");
}

TEST_F(PcdErrors, CompressedSizeDisagreesWithPoints) {
  const std::string path =
      file_with(compressed_file(2, 13, 12, testing::lzf_literals("123456789abc")));
  EXPECT_INPUT_ERROR(read_pcd(path), path,
                     "uncompressed size 12 does not match POINTS*point size = 24");
  // A 4 GiB-scale claim is refused before any allocation.
  const std::string big = file_with(compressed_file(357913941, 1, 4294967292u, "x"));
  EXPECT_INPUT_ERROR(read_pcd(big), big, "uncompressed size 4294967292 cannot come from 1");
}

TEST_F(PcdErrors, CompressedSizeImpossibleForTheStream) {
  // 100000 points of 12 bytes cannot come from 10 bytes of LZF (at most 88 bytes per byte).
  const std::string path = file_with(compressed_file(100000, 10, 1200000, std::string(10, '\0')));
  EXPECT_INPUT_ERROR(read_pcd(path), path, "uncompressed size 1200000 cannot come from 10");
}

TEST_F(PcdErrors, CorruptLzfStream) {
  // A back-reference as the first chunk points before the start of the output.
  const std::string backwards = file_with(compressed_file(1, 2, 12, std::string("\x20\x05", 2)));
  EXPECT_INPUT_ERROR(read_pcd(backwards), backwards, "corrupt compressed data: back-reference");
  // A stream that stops short of the declared size.
  const std::string short_stream =
      file_with(compressed_file(1, 5, 12, testing::lzf_literals("abcd")));
  EXPECT_INPUT_ERROR(read_pcd(short_stream), short_stream, "corrupt compressed data: stream ends");
}

}  // namespace
}  // namespace iilfm::io
