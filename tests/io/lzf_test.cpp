#include "../../src/io/lzf.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace iilfm::io {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes decompress_or_fail(const Bytes& packed, std::size_t size) {
  Bytes out(size);
  std::string problem;
  EXPECT_TRUE(lzf_decompress(packed.data(), packed.size(), out.data(), out.size(), problem))
      << problem;
  return out;
}

std::string rejection(const Bytes& packed, std::size_t output_size) {
  Bytes out(output_size);
  std::string problem;
  EXPECT_FALSE(lzf_decompress(packed.data(), packed.size(), out.data(), out.size(), problem));
  EXPECT_FALSE(problem.empty());
  return problem;
}

Bytes random_bytes(std::size_t size, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Bytes data(size);
  for (auto& b : data) b = static_cast<std::uint8_t>(rng());
  return data;
}

TEST(Lzf, RoundTripsRandomData) {
  for (const std::size_t size : {0, 1, 2, 3, 31, 32, 33, 1000, 200000}) {
    const Bytes data = random_bytes(size, static_cast<std::uint32_t>(size));
    const Bytes packed = lzf_compress(data.data(), data.size());
    // Incompressible: literal runs only, one control byte per 32 bytes.
    EXPECT_LE(packed.size(), size + (size + 31) / 32) << size;
    EXPECT_EQ(decompress_or_fail(packed, size), data) << size;
  }
}

TEST(Lzf, CompressesAndRoundTripsRepetitiveData) {
  const Bytes zeros(1 << 20, 0);
  const Bytes packed_zeros = lzf_compress(zeros.data(), zeros.size());
  EXPECT_LT(packed_zeros.size(), zeros.size() / 80);  // long back-references: 264 bytes per 3
  EXPECT_EQ(decompress_or_fail(packed_zeros, zeros.size()), zeros);

  Bytes pattern;
  for (int i = 0; i < 50000; ++i) pattern.push_back(static_cast<std::uint8_t>("abcdefg"[i % 7]));
  const Bytes packed_pattern = lzf_compress(pattern.data(), pattern.size());
  EXPECT_LT(packed_pattern.size(), pattern.size() / 50);
  EXPECT_EQ(decompress_or_fail(packed_pattern, pattern.size()), pattern);

  // A float column with slowly changing values, like a LiDAR field block.
  std::vector<float> column(100000);
  for (std::size_t i = 0; i < column.size(); ++i) column[i] = static_cast<float>(i / 64);
  const auto* raw = reinterpret_cast<const std::uint8_t*>(column.data());
  const Bytes floats(raw, raw + column.size() * sizeof(float));
  const Bytes packed_floats = lzf_compress(floats.data(), floats.size());
  EXPECT_LT(packed_floats.size(), floats.size() / 4);
  EXPECT_EQ(decompress_or_fail(packed_floats, floats.size()), floats);
}

TEST(Lzf, DecodesHandWrittenStream) {
  // Literal "abc", then a back-reference of length 1 + 2 = 3 at distance 2 + 1 = 3: "abcabc".
  const Bytes short_reference = {0x02, 'a', 'b', 'c', 0x20, 0x02};
  const Bytes abcabc = {'a', 'b', 'c', 'a', 'b', 'c'};
  EXPECT_EQ(decompress_or_fail(short_reference, 6), abcabc);

  // Literal "x", then a long back-reference (code 7 + 3 = 10, length 12) at distance 1 that
  // overlaps the bytes it writes: thirteen 'x'.
  const Bytes overlapping = {0x00, 'x', 0xE0, 0x03, 0x00};
  EXPECT_EQ(decompress_or_fail(overlapping, 13), Bytes(13, 'x'));
}

TEST(Lzf, RejectsCorruptStreams) {
  EXPECT_NE(rejection({0x20, 0x05}, 10).find("back"), std::string::npos);  // before the start
  EXPECT_NE(rejection({0x05, 'a', 'b'}, 10).find("past the input"), std::string::npos);
  EXPECT_NE(rejection({0x03, 'a', 'b', 'c', 'd'}, 2).find("overrun"), std::string::npos);
  EXPECT_NE(rejection({0x00, 'a', 0x20, 0x00}, 2).find("overrun"), std::string::npos);
  EXPECT_NE(rejection({0x00, 'a', 0xE0}, 20).find("cut off"), std::string::npos);
  EXPECT_NE(rejection({0x00, 'a', 0x20}, 20).find("cut off"), std::string::npos);
  EXPECT_NE(rejection({0x01, 'a', 'b'}, 5).find("ends after 2 of 5"), std::string::npos);
}

TEST(Lzf, SurvivesRandomCorruption) {
  // Whatever the damage, the decoder must stop cleanly (the sanitizer build checks the memory).
  Bytes data;
  for (int i = 0; i < 20000; ++i) data.push_back(static_cast<std::uint8_t>((i * 7) % 251 / 3));
  const Bytes packed = lzf_compress(data.data(), data.size());
  std::mt19937 rng(42);
  int rejected = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Bytes damaged = packed;
    for (int k = 0; k < 3; ++k) damaged[rng() % damaged.size()] = static_cast<std::uint8_t>(rng());
    damaged.resize(damaged.size() - rng() % 4);
    Bytes out(data.size());
    std::string problem;
    if (!lzf_decompress(damaged.data(), damaged.size(), out.data(), out.size(), problem)) {
      ++rejected;
    }
  }
  EXPECT_GT(rejected, 1000);
}

}  // namespace
}  // namespace iilfm::io
