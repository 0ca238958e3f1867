// DATA binary (point-major records) and binary_compressed (LZF over field-major columns).
#include <algorithm>
#include <cstring>
#include <memory>

#include "iilfm/error.hpp"
#include "lzf.hpp"
#include "pcd_body.hpp"
#include "point_filter.hpp"

namespace iilfm::io {
namespace {

struct ColumnView {
  const std::uint8_t* first;  // element 0 of the field for the first point of the range
  std::size_t stride;         // bytes from one point's element to the next
};

// Decodes points [first, first + n) into the cloud columns from index `slot` on, one column at a
// time; `locate(field, first)` says where a field's values are. The block's records stay in cache
// while each column makes its pass over them.
template <typename Locate>
void decode_block(const PcdHeader& header, const Locate& locate, std::size_t first, std::size_t n,
                  PointCloud& cloud, std::size_t slot) {
  const auto decode = [&](int field_index, auto* column) {
    const PcdField& field = header.fields[field_index];
    const ColumnView view = locate(field, first);
    decode_column(field.type, view.first, view.stride, n, column + slot);
  };
  const PcdColumnSources& s = header.sources;
  decode(s.x, cloud.x.data());
  decode(s.y, cloud.y.data());
  decode(s.z, cloud.z.data());
  if (s.intensity != PcdColumnSources::kAbsent) decode(s.intensity, cloud.intensity.data());
  if (s.ring != PcdColumnSources::kAbsent) decode(s.ring, cloud.ring.data());
  if (s.time != PcdColumnSources::kAbsent) decode(s.time, cloud.time.data());
}

template <typename Locate>
void decode_all_points(const PcdHeader& header, const Locate& locate, LoadedCloud& out) {
  const bool with_ring = header.sources.ring != PcdColumnSources::kAbsent;
  const bool with_time = header.sources.time != PcdColumnSources::kAbsent;
  const std::size_t n = static_cast<std::size_t>(header.points);
  out.cloud.reserve(n, with_ring, with_time);
  out.stats.points_in_file = n;
  for (std::size_t first = 0; first < n; first += kDecodeBlockPoints) {
    const std::size_t count = std::min(kDecodeBlockPoints, n - first);
    const std::size_t slot = grow_columns(out.cloud, count, with_ring, with_time);
    decode_block(header, locate, first, count, out.cloud, slot);
    drop_invalid_points(out.cloud, slot, out.stats);
  }
}

std::size_t body_size(const PcdHeader& header, const std::string& path) {
  std::size_t bytes = 0;
  if (__builtin_mul_overflow(header.points, header.point_size, &bytes)) {
    throw file_error(path, "POINTS " + std::to_string(header.points) + " times the " +
                               std::to_string(header.point_size) + "-byte point overflows");
  }
  return bytes;
}

std::uint32_t read_u32_le(const std::uint8_t* p) {
  std::uint32_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace

void decode_pcd_binary(const FileBytes& file, const PcdHeader& header, const std::string& path,
                       LoadedCloud& out) {
  const std::size_t needed = body_size(header, path);
  const std::size_t available = file.size() - header.data_offset;
  if (needed > available) {
    throw file_error(path, "truncated binary data: expected " + std::to_string(needed) +
                               " bytes, found " + std::to_string(available));
  }
  const std::uint8_t* records = file.begin() + header.data_offset;
  const std::size_t stride = header.point_size;
  const auto locate = [&](const PcdField& field, std::size_t first) {
    return ColumnView{records + first * stride + field.byte_offset, stride};
  };
  decode_all_points(header, locate, out);
}

void decode_pcd_binary_compressed(const FileBytes& file, const PcdHeader& header,
                                  const std::string& path, LoadedCloud& out) {
  constexpr std::size_t kSizeHeader = 8;  // uint32 compressed size, uint32 uncompressed size
  const std::size_t available = file.size() - header.data_offset;
  if (available < kSizeHeader) {
    throw file_error(path, "truncated binary_compressed data: " + std::to_string(available) +
                               " bytes, the size header alone needs 8");
  }
  const std::uint8_t* body = file.begin() + header.data_offset;
  const std::size_t compressed = read_u32_le(body);
  const std::size_t uncompressed = read_u32_le(body + 4);
  if (compressed > available - kSizeHeader) {
    throw file_error(path, "truncated compressed data: expected " + std::to_string(compressed) +
                               " bytes, found " + std::to_string(available - kSizeHeader));
  }
  // The field is 32 bits wide, so a size that matches is also below 4 GiB.
  const std::size_t needed = body_size(header, path);
  if (uncompressed != needed) {
    throw file_error(path, "uncompressed size " + std::to_string(uncompressed) +
                               " does not match POINTS*point size = " + std::to_string(needed));
  }
  if (uncompressed > compressed * kLzfMaxExpansion) {
    throw file_error(path, "uncompressed size " + std::to_string(uncompressed) +
                               " cannot come from " + std::to_string(compressed) +
                               " compressed bytes");
  }

  std::unique_ptr<std::uint8_t[]> columns(new std::uint8_t[uncompressed]);
  std::string problem;
  if (!lzf_decompress(body + kSizeHeader, compressed, columns.get(), uncompressed, problem)) {
    throw file_error(path, "corrupt compressed data: " + problem);
  }
  // Field-major: each field's values for all points follow each other, fields in header order.
  const std::size_t n = static_cast<std::size_t>(header.points);
  const auto locate = [&](const PcdField& field, std::size_t first) {
    const std::size_t stride = field.size * field.count;
    return ColumnView{columns.get() + n * field.byte_offset + first * stride, stride};
  };
  decode_all_points(header, locate, out);
}

}  // namespace iilfm::io
