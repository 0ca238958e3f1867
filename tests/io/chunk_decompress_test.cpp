// The lz4 frame decompression of ROS 1 bag and MCAP chunks and the zstd one of MCAP chunks: one
// decompression context per thread is reused from chunk to chunk, so a frame that stopped half way
// (damaged or cut short) must not leak into the next one; sizes are those declared, never more.
#include "../../src/io/chunk_decompress.hpp"

#include <gtest/gtest.h>
#include <lz4frame.h>
#include <zstd.h>

#include <cstdint>
#include <random>
#include <vector>

namespace iilfm::io {
namespace {

// About `size` bytes of point-cloud-like data (repeated fields with noise): compressible.
std::vector<std::uint8_t> sample_bytes(std::size_t size, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> out(size);
  for (std::size_t i = 0; i < size; ++i)
    out[i] = static_cast<std::uint8_t>(i % 16 < 12 ? i % 7 : rng());
  return out;
}

// One lz4 frame of 4 MB blocks, as roslz4 writes them.
std::vector<std::uint8_t> lz4_frame(const std::vector<std::uint8_t>& data) {
  LZ4F_preferences_t preferences{};
  preferences.frameInfo.blockSizeID = LZ4F_max4MB;
  std::vector<std::uint8_t> out(LZ4F_compressFrameBound(data.size(), &preferences));
  const std::size_t size =
      LZ4F_compressFrame(out.data(), out.size(), data.data(), data.size(), &preferences);
  EXPECT_FALSE(LZ4F_isError(size));
  out.resize(size);
  return out;
}

TEST(ChunkDecompress, Lz4FramesReadRightAfterOneCutShortOrDamaged) {
  const std::vector<std::uint8_t> first = sample_bytes(3'000'000, 1),
                                  second = sample_bytes(700'000, 2);
  const std::vector<std::uint8_t> first_lz4 = lz4_frame(first), second_lz4 = lz4_frame(second);
  std::vector<std::uint8_t> out;
  ASSERT_EQ(decompress_lz4_frame(first_lz4.data(), first_lz4.size(), first.size(), out), "");
  EXPECT_EQ(out, first);

  // Cut short: the context stops in the middle of a block.
  const std::string cut =
      decompress_lz4_frame(first_lz4.data(), first_lz4.size() / 2, first.size(), out);
  EXPECT_EQ(cut, "lz4 data ends early");
  ASSERT_EQ(decompress_lz4_frame(second_lz4.data(), second_lz4.size(), second.size(), out), "");
  EXPECT_EQ(out, second);

  // Damaged: bytes flipped inside the first block.
  std::vector<std::uint8_t> damaged = first_lz4;
  for (std::size_t i = 100; i < 140; ++i) damaged[i] ^= 0x5a;
  const std::string problem =
      decompress_lz4_frame(damaged.data(), damaged.size(), first.size(), out);
  EXPECT_NE(problem, "");
  ASSERT_EQ(decompress_lz4_frame(first_lz4.data(), first_lz4.size(), first.size(), out), "");
  EXPECT_EQ(out, first);
}

std::vector<std::uint8_t> zstd_frame(const std::vector<std::uint8_t>& data) {
  std::vector<std::uint8_t> out(ZSTD_compressBound(data.size()));
  const std::size_t size = ZSTD_compress(out.data(), out.size(), data.data(), data.size(), 3);
  EXPECT_FALSE(ZSTD_isError(size));
  out.resize(size);
  return out;
}

TEST(ChunkDecompress, ZstdFramesWholeCutDamagedOrOfAnotherSize) {
  const std::vector<std::uint8_t> first = sample_bytes(3'000'000, 3),
                                  second = sample_bytes(700'000, 4);
  const std::vector<std::uint8_t> first_zstd = zstd_frame(first), second_zstd = zstd_frame(second);
  std::vector<std::uint8_t> out;
  ASSERT_EQ(decompress_zstd(first_zstd.data(), first_zstd.size(), first.size(), out), "");
  EXPECT_EQ(out, first);

  // Two frames one after the other make one chunk (the format allows it).
  std::vector<std::uint8_t> both = first_zstd, joined = first;
  both.insert(both.end(), second_zstd.begin(), second_zstd.end());
  joined.insert(joined.end(), second.begin(), second.end());
  ASSERT_EQ(decompress_zstd(both.data(), both.size(), joined.size(), out), "");
  EXPECT_EQ(out, joined);

  // Cut short, then the next chunk reads whole.
  EXPECT_EQ(decompress_zstd(first_zstd.data(), first_zstd.size() / 2, first.size(), out),
            "zstd data ends early");
  ASSERT_EQ(decompress_zstd(second_zstd.data(), second_zstd.size(), second.size(), out), "");
  EXPECT_EQ(out, second);

  // A declared size the data does not match, either way: an error, and never more than declared
  // plus one byte allocated.
  EXPECT_EQ(decompress_zstd(first_zstd.data(), first_zstd.size(), first.size() - 1, out),
            "zstd data decompresses to more than the " + std::to_string(first.size() - 1) +
                " bytes declared");
  EXPECT_LE(out.size(), first.size());
  EXPECT_EQ(decompress_zstd(second_zstd.data(), second_zstd.size(), second.size() + 10, out),
            "zstd data decompresses to " + std::to_string(second.size()) + " bytes, not the " +
                std::to_string(second.size() + 10) + " bytes declared");

  // Not zstd at all.
  const std::vector<std::uint8_t> noise = sample_bytes(1000, 5);
  EXPECT_EQ(decompress_zstd(noise.data(), noise.size(), 1000, out).rfind("zstd data corrupt", 0),
            0u);
  ASSERT_EQ(decompress_zstd(first_zstd.data(), first_zstd.size(), first.size(), out), "");
  EXPECT_EQ(out, first);
}

}  // namespace
}  // namespace iilfm::io
