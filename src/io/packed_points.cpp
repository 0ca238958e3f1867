#include "packed_points.hpp"

#include <algorithm>
#include <cctype>
#include <string_view>

#include "byte_cursor.hpp"
#include "point_filter.hpp"

namespace iilfm::io {
namespace {

std::string role_name(const std::string& name) {
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  constexpr std::string_view kPrefix = "scalar_";
  if (lower.size() > kPrefix.size() && lower.compare(0, kPrefix.size(), kPrefix) == 0)
    lower.erase(0, kPrefix.size());
  return lower;
}

// The first field whose name is one of `names`, in the order of `names`.
int find_field(const std::vector<std::string>& normalised,
               std::initializer_list<std::string_view> names) {
  for (std::string_view wanted : names) {
    for (std::size_t i = 0; i < normalised.size(); ++i)
      if (normalised[i] == wanted) return static_cast<int>(i);
  }
  return -1;
}

template <typename Src, typename Dst>
void decode_swapped_column(const std::uint8_t* first, std::size_t stride, std::size_t n, Dst* out) {
  for (std::size_t i = 0; i < n; ++i) {
    Src v;
    std::memcpy(&v, first + i * stride, sizeof v);
    out[i] = convert_scalar<Dst>(byte_swapped(v));
  }
}

template <typename Dst>
void decode_any_order(ScalarType type, const std::uint8_t* first, std::size_t stride, std::size_t n,
                      bool big_endian, Dst* out) {
  if (!big_endian) return decode_column(type, first, stride, n, out);
  switch (type) {
    case ScalarType::kI8:
      return decode_swapped_column<std::int8_t>(first, stride, n, out);
    case ScalarType::kI16:
      return decode_swapped_column<std::int16_t>(first, stride, n, out);
    case ScalarType::kI32:
      return decode_swapped_column<std::int32_t>(first, stride, n, out);
    case ScalarType::kI64:
      return decode_swapped_column<std::int64_t>(first, stride, n, out);
    case ScalarType::kU8:
      return decode_swapped_column<std::uint8_t>(first, stride, n, out);
    case ScalarType::kU16:
      return decode_swapped_column<std::uint16_t>(first, stride, n, out);
    case ScalarType::kU32:
      return decode_swapped_column<std::uint32_t>(first, stride, n, out);
    case ScalarType::kU64:
      return decode_swapped_column<std::uint64_t>(first, stride, n, out);
    case ScalarType::kF32:
      return decode_swapped_column<float>(first, stride, n, out);
    case ScalarType::kF64:
      return decode_swapped_column<double>(first, stride, n, out);
  }
}

}  // namespace

std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::kI8:
    case ScalarType::kU8:
      return 1;
    case ScalarType::kI16:
    case ScalarType::kU16:
      return 2;
    case ScalarType::kI32:
    case ScalarType::kU32:
    case ScalarType::kF32:
      return 4;
    case ScalarType::kI64:
    case ScalarType::kU64:
    case ScalarType::kF64:
      return 8;
  }
  return 0;
}

PackedRoles find_roles_by_name(const std::vector<std::string>& names) {
  std::vector<std::string> normalised;
  normalised.reserve(names.size());
  for (const std::string& name : names) normalised.push_back(role_name(name));
  PackedRoles roles;
  roles.x = find_field(normalised, {"x"});
  roles.y = find_field(normalised, {"y"});
  roles.z = find_field(normalised, {"z"});
  roles.intensity = find_field(normalised, {"intensity", "signal", "reflectivity", "i"});
  roles.ring = find_field(normalised, {"ring", "channel", "line"});
  roles.time = find_field(normalised, {"time", "timestamp", "t"});
  return roles;
}

PackedRoles find_packed_roles(const std::vector<PackedField>& fields) {
  std::vector<std::string> names;
  names.reserve(fields.size());
  for (const PackedField& f : fields) names.push_back(f.name);
  return find_roles_by_name(names);
}

void decode_packed_records(const std::uint8_t* first, std::size_t n, std::size_t stride,
                           const std::vector<PackedField>& fields, const PackedRoles& roles,
                           bool big_endian, LoadedCloud& out) {
  const bool with_ring = roles.ring >= 0, with_time = roles.time >= 0;
  out.stats.points_in_file += n;
  out.cloud.reserve(out.cloud.size() + n, with_ring, with_time);
  auto column = [&](int role, std::size_t block_first, std::size_t count, auto* dst) {
    const PackedField& f = fields[static_cast<std::size_t>(role)];
    decode_any_order(f.type, first + block_first * stride + f.offset, stride, count, big_endian,
                     dst);
  };
  for (std::size_t done = 0; done < n; done += kDecodeBlockPoints) {
    const std::size_t count = std::min(kDecodeBlockPoints, n - done);
    const std::size_t slot = grow_columns(out.cloud, count, with_ring, with_time);
    PointCloud& c = out.cloud;
    column(roles.x, done, count, c.x.data() + slot);
    column(roles.y, done, count, c.y.data() + slot);
    column(roles.z, done, count, c.z.data() + slot);
    if (roles.intensity >= 0) column(roles.intensity, done, count, c.intensity.data() + slot);
    if (with_ring) column(roles.ring, done, count, c.ring.data() + slot);
    if (with_time) column(roles.time, done, count, c.time.data() + slot);
    drop_invalid_points(c, slot, out.stats);
  }
}

}  // namespace iilfm::io
