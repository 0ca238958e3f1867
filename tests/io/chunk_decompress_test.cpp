// The lz4 frame decompression of ROS 1 bag chunks: one decompression context per thread is reused
// from chunk to chunk, so a frame that stopped half way (damaged or cut short) must not leak into
// the next one.
#include "../../src/io/chunk_decompress.hpp"

#include <gtest/gtest.h>
#include <lz4frame.h>

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

}  // namespace
}  // namespace iilfm::io
