#include "chunk_decompress.hpp"

#include <bzlib.h>
#include <lz4frame.h>

#include <climits>
#include <memory>

namespace iilfm::io {

std::string decompress_bz2(const std::uint8_t* data, std::size_t size, std::size_t expected,
                           std::vector<std::uint8_t>& out) {
  if (size > UINT_MAX || expected >= UINT_MAX) return "bz2 chunk too large";
  out.resize(expected + 1);  // one spare byte tells "exactly expected" from "more than expected"
  unsigned int produced = static_cast<unsigned int>(out.size());
  const int status =
      BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data()), &produced,
                                 const_cast<char*>(reinterpret_cast<const char*>(data)),
                                 static_cast<unsigned int>(size), 0, 0);
  if (status == BZ_OUTBUFF_FULL)
    return "bz2 data decompresses to more than the " + std::to_string(expected) + " bytes declared";
  if (status == BZ_DATA_ERROR || status == BZ_DATA_ERROR_MAGIC) return "bz2 data corrupt";
  if (status == BZ_UNEXPECTED_EOF) return "bz2 data ends early";
  if (status != BZ_OK) return "bz2 decompression failed (code " + std::to_string(status) + ")";
  if (produced != expected)
    return "bz2 data decompresses to " + std::to_string(produced) + " bytes, " +
           std::to_string(expected) + " declared";
  out.resize(expected);
  return {};
}

std::string decompress_lz4_frame(const std::uint8_t* data, std::size_t size, std::size_t expected,
                                 std::vector<std::uint8_t>& out) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
    return "lz4 context allocation failed";
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> context(
      raw, &LZ4F_freeDecompressionContext);
  out.resize(expected + 1);
  std::size_t consumed = 0, produced = 0;
  std::size_t hint = 1;
  while (consumed < size && hint != 0) {
    std::size_t in_size = size - consumed, out_size = out.size() - produced;
    hint = LZ4F_decompress(context.get(), out.data() + produced, &out_size, data + consumed,
                           &in_size, nullptr);
    if (LZ4F_isError(hint))
      return std::string("lz4 data corrupt (") + LZ4F_getErrorName(hint) + ")";
    consumed += in_size;
    produced += out_size;
    if (in_size == 0 && out_size == 0) break;  // no progress: the output is full
  }
  if (hint != 0) return "lz4 data ends early";
  if (produced != expected)
    return "lz4 data decompresses to " + std::to_string(produced) + " bytes, " +
           std::to_string(expected) + " declared";
  out.resize(expected);
  return {};
}

}  // namespace iilfm::io
