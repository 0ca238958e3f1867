// LZF, the byte-oriented LZ77 variant PCL uses for DATA binary_compressed.
//
// The stream is a sequence of chunks, each introduced by a control byte c:
//   c < 32:  a literal run; the next c + 1 bytes are copied to the output as they are.
//   c >= 32: a back-reference; length code L = c >> 5 (if L == 7, one more byte is added to it),
//            then one byte b; it copies L + 2 bytes starting (((c & 31) << 8) | b) + 1 bytes back
//            in the output, byte by byte, so a copy may overlap the bytes it produces.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace iilfm::io {

// The most output one input byte can produce (a 3-byte back-reference copying 264 bytes), so a
// claimed uncompressed size above input_size * kLzfMaxExpansion is a corrupt header.
inline constexpr std::size_t kLzfMaxExpansion = 88;

// Compresses `size` bytes. Always succeeds; incompressible input grows by 1 byte per 32.
std::vector<std::uint8_t> lzf_compress(const std::uint8_t* data, std::size_t size);

// Decompresses `input` into exactly `output_size` bytes at `output`. Returns false and says why in
// `problem` when the stream is corrupt: a chunk runs past the input, a back-reference points before
// the start of the output, the output would overrun, or the stream ends short of `output_size`.
bool lzf_decompress(const std::uint8_t* input, std::size_t input_size, std::uint8_t* output,
                    std::size_t output_size, std::string& problem);

}  // namespace iilfm::io
