#include "chunk_decompress.hpp"

#include <bzlib.h>
#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <climits>
#include <memory>

namespace iilfm::io {
namespace {

// The output grows with what the data really produces, up to one byte past the declared size (that
// byte tells "exactly expected" from "more"): a damaged header declaring gigabytes must not decide
// the allocation on its own.
constexpr std::size_t kFirstCapacity = std::size_t{1} << 20;

bool grow(std::vector<std::uint8_t>& out, std::size_t limit) {
  if (out.size() >= limit) return false;
  out.resize(std::min(limit, std::max(kFirstCapacity, out.size() * 2)));
  return true;
}

std::string size_problem(const char* codec, std::size_t produced, std::size_t expected) {
  if (produced > expected)
    return std::string(codec) + " data decompresses to more than the " + std::to_string(expected) +
           " bytes declared";
  return std::string(codec) + " data decompresses to " + std::to_string(produced) +
         " bytes, not the " + std::to_string(expected) + " bytes declared";
}

}  // namespace

std::string decompress_bz2(const std::uint8_t* data, std::size_t size, std::size_t expected,
                           std::vector<std::uint8_t>& out) {
  if (size > UINT_MAX || expected >= UINT_MAX) return "bz2 chunk too large";
  bz_stream stream{};
  if (BZ2_bzDecompressInit(&stream, 0, 0) != BZ_OK) return "bz2 context allocation failed";
  const std::unique_ptr<bz_stream, int (*)(bz_stream*)> closer(&stream, &BZ2_bzDecompressEnd);
  stream.next_in = const_cast<char*>(reinterpret_cast<const char*>(data));
  stream.avail_in = static_cast<unsigned int>(size);
  out.clear();
  std::size_t produced = 0;
  int status = BZ_OK;
  while (status == BZ_OK) {
    if (produced == out.size() && !grow(out, expected + 1)) break;
    stream.next_out = reinterpret_cast<char*>(out.data() + produced);
    stream.avail_out = static_cast<unsigned int>(out.size() - produced);
    status = BZ2_bzDecompress(&stream);
    produced = out.size() - stream.avail_out;
    if (status == BZ_OK && stream.avail_in == 0 && stream.avail_out != 0) {
      status = BZ_UNEXPECTED_EOF;  // all input used, room left, stream not ended
    }
  }
  if (status == BZ_DATA_ERROR || status == BZ_DATA_ERROR_MAGIC) return "bz2 data corrupt";
  if (status == BZ_UNEXPECTED_EOF) return "bz2 data ends early";
  if (status != BZ_OK && status != BZ_STREAM_END)
    return "bz2 decompression failed (code " + std::to_string(status) + ")";
  if (status != BZ_STREAM_END || produced != expected)
    return size_problem("bz2", status == BZ_STREAM_END ? produced : expected + 1, expected);
  out.resize(expected);
  return {};
}

std::string decompress_lz4_frame(const std::uint8_t* data, std::size_t size, std::size_t expected,
                                 std::vector<std::uint8_t>& out) {
  // One context per thread, reset for each frame: a new one allocated its block buffer (up to
  // 4 MB, as roslz4 writes) afresh for every chunk, and the page faults of filling it cost more
  // than the decompression of a VLP-16 recording's chunks.
  using Context = std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)>;
  thread_local Context context(nullptr, &LZ4F_freeDecompressionContext);
  if (!context) {
    LZ4F_dctx* raw = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
      return "lz4 context allocation failed";
    context.reset(raw);
  }
  LZ4F_resetDecompressionContext(context.get());  // also after a frame that stopped with an error
  out.clear();
  std::size_t consumed = 0, produced = 0;
  std::size_t hint = 1;
  while (consumed < size && hint != 0) {
    if (produced == out.size() && !grow(out, expected + 1)) break;
    std::size_t in_size = size - consumed, out_size = out.size() - produced;
    hint = LZ4F_decompress(context.get(), out.data() + produced, &out_size, data + consumed,
                           &in_size, nullptr);
    if (LZ4F_isError(hint))
      return std::string("lz4 data corrupt (") + LZ4F_getErrorName(hint) + ")";
    consumed += in_size;
    produced += out_size;
    if (in_size == 0 && out_size == 0 && produced < out.size()) break;  // no progress
  }
  if (produced > expected) return size_problem("lz4", produced, expected);
  if (hint != 0) return "lz4 data ends early";
  if (produced != expected) return size_problem("lz4", produced, expected);
  out.resize(expected);
  return {};
}

std::string decompress_zstd(const std::uint8_t* data, std::size_t size, std::size_t expected,
                            std::vector<std::uint8_t>& out) {
  // Streaming, like the lz4 frames: the frame header's content size is not trusted either. One
  // context per thread, reset for each chunk.
  using Context = std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)>;
  thread_local Context context(nullptr, &ZSTD_freeDCtx);
  if (!context) {
    context.reset(ZSTD_createDCtx());
    if (!context) return "zstd context allocation failed";
  }
  ZSTD_DCtx_reset(context.get(), ZSTD_reset_session_only);
  out.clear();
  ZSTD_inBuffer in{data, size, 0};
  std::size_t produced = 0, hint = 1;
  while (in.pos < size || hint != 0) {
    if (produced == out.size() && !grow(out, expected + 1)) break;
    ZSTD_outBuffer target{out.data(), out.size(), produced};
    const std::size_t before = in.pos;
    hint = ZSTD_decompressStream(context.get(), &target, &in);
    if (ZSTD_isError(hint))
      return std::string("zstd data corrupt (") + ZSTD_getErrorName(hint) + ")";
    const bool progress = in.pos != before || target.pos != produced;
    produced = target.pos;
    if (!progress && produced < out.size()) break;  // all input used, frame not ended
  }
  if (produced > expected) return size_problem("zstd", produced, expected);
  if (hint != 0) return "zstd data ends early";
  if (produced != expected) return size_problem("zstd", produced, expected);
  out.resize(expected);
  return {};
}

}  // namespace iilfm::io
