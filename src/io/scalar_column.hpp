// Decoding one numeric column of a packed record array into a typed vector: the inner loop of the
// binary readers. The source type is chosen once per column, so the per-value work is one memcpy
// (an unaligned load after optimisation) and one conversion.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace iilfm::io {

enum class ScalarType : std::uint8_t { kI8, kI16, kI32, kI64, kU8, kU16, kU32, kU64, kF32, kF64 };

// Converts a stored value to a cloud column type without undefined behaviour: doubles beyond the
// float range become +-inf (then dropped as non-finite), ring numbers saturate to 0..65535.
template <typename Dst, typename Src>
Dst convert_scalar(Src v) {
  if constexpr (std::is_same_v<Dst, float> && std::is_same_v<Src, double>) {
    // Values from FLT_MAX up to half a float step above it round to FLT_MAX (the shortest decimal
    // of FLT_MAX, 3.4028235e+38, is such a value); only those beyond overflow.
    constexpr double kOverflow = 0x1.ffffffp127;
    if (v >= kOverflow) return std::numeric_limits<float>::infinity();
    if (v <= -kOverflow) return -std::numeric_limits<float>::infinity();
    return static_cast<float>(v);
  } else if constexpr (std::is_same_v<Dst, std::uint16_t>) {
    constexpr std::uint16_t kTop = std::numeric_limits<std::uint16_t>::max();
    if constexpr (std::is_floating_point_v<Src>) {
      if (!(v >= 0)) return 0;  // also NaN
      return v > static_cast<Src>(kTop) ? kTop : static_cast<std::uint16_t>(v);
    } else {
      if constexpr (std::is_signed_v<Src>) {
        if (v < 0) return 0;
      }
      return static_cast<std::uint64_t>(v) > kTop ? kTop : static_cast<std::uint16_t>(v);
    }
  } else {
    return static_cast<Dst>(v);
  }
}

template <typename Src, typename Dst>
void decode_typed_column(const std::uint8_t* first, std::size_t stride, std::size_t n, Dst* out) {
  for (std::size_t i = 0; i < n; ++i) {
    Src v;
    std::memcpy(&v, first + i * stride, sizeof v);
    out[i] = convert_scalar<Dst>(v);
  }
}

// Reads n values of `type`, the first at `first` and each next one `stride` bytes further, in the
// host byte order (PCD and KITTI files are little-endian, as are the hosts we build for).
template <typename Dst>
void decode_column(ScalarType type, const std::uint8_t* first, std::size_t stride, std::size_t n,
                   Dst* out) {
  switch (type) {
    case ScalarType::kI8:
      return decode_typed_column<std::int8_t>(first, stride, n, out);
    case ScalarType::kI16:
      return decode_typed_column<std::int16_t>(first, stride, n, out);
    case ScalarType::kI32:
      return decode_typed_column<std::int32_t>(first, stride, n, out);
    case ScalarType::kI64:
      return decode_typed_column<std::int64_t>(first, stride, n, out);
    case ScalarType::kU8:
      return decode_typed_column<std::uint8_t>(first, stride, n, out);
    case ScalarType::kU16:
      return decode_typed_column<std::uint16_t>(first, stride, n, out);
    case ScalarType::kU32:
      return decode_typed_column<std::uint32_t>(first, stride, n, out);
    case ScalarType::kU64:
      return decode_typed_column<std::uint64_t>(first, stride, n, out);
    case ScalarType::kF32:
      return decode_typed_column<float>(first, stride, n, out);
    case ScalarType::kF64:
      return decode_typed_column<double>(first, stride, n, out);
  }
}

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the cloud readers and writer assume a little-endian host");

}  // namespace iilfm::io
