// The compressions of bag chunks: bz2 (libbz2) and lz4 (liblz4's frame format, as roslz4 and MCAP
// write it) in ROS 1 bags, lz4 and zstd (libzstd, one or more frames) in MCAP files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace iilfm::io {

// Decompresses `size` bytes into `out`, which must come out exactly `expected` bytes long. Returns
// an empty string on success, else the problem ("bz2 data corrupt", "lz4 ... ").
std::string decompress_bz2(const std::uint8_t* data, std::size_t size, std::size_t expected,
                           std::vector<std::uint8_t>& out);
std::string decompress_lz4_frame(const std::uint8_t* data, std::size_t size, std::size_t expected,
                                 std::vector<std::uint8_t>& out);
std::string decompress_zstd(const std::uint8_t* data, std::size_t size, std::size_t expected,
                            std::vector<std::uint8_t>& out);

}  // namespace iilfm::io
