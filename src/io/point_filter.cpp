#include "point_filter.hpp"

#include <cstdint>
#include <cstring>

namespace iilfm::io {
namespace {

std::uint32_t bits_of(float v) {
  std::uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  return bits;
}

// IEEE-754 bit tests rather than std::isfinite and ==, so the scan below vectorises.
constexpr std::uint32_t kExponent = 0x7f800000u;   // all ones: Inf or NaN
constexpr std::uint32_t kMagnitude = 0x7fffffffu;  // zero for +0 and -0

// 0 or 1 as an integer, so the tests combine with a branch-free `&` (no bool short-circuit).
std::uint32_t finite(std::uint32_t bits) { return (bits & kExponent) != kExponent ? 1u : 0u; }
std::uint32_t non_zero(std::uint32_t bx, std::uint32_t by, std::uint32_t bz) {
  return ((bx | by | bz) & kMagnitude) != 0 ? 1u : 0u;
}

void set_size(PointCloud& cloud, std::size_t n, bool with_ring, bool with_time) {
  cloud.x.resize(n);
  cloud.y.resize(n);
  cloud.z.resize(n);
  cloud.intensity.resize(n);
  if (with_ring) cloud.ring.resize(n);
  if (with_time) cloud.time.resize(n);
}

// Moves each kept point down to slot `kept`; the slot only advances for a kept point, so the loop
// has no branches and later points overwrite the rejected ones.
template <bool kWithRing, bool kWithTime>
void compact(PointCloud& cloud, std::size_t first, CloudStats& stats) {
  const std::size_t end = cloud.size();
  float* x = cloud.x.data();
  float* y = cloud.y.data();
  float* z = cloud.z.data();
  float* intensity = cloud.intensity.data();
  std::uint16_t* ring = cloud.ring.data();
  double* time = cloud.time.data();
  std::size_t kept = first, non_finite = 0, zero = 0;
  for (std::size_t i = first; i < end; ++i) {
    const std::uint32_t bx = bits_of(x[i]), by = bits_of(y[i]), bz = bits_of(z[i]);
    const std::uint32_t ok = finite(bx) & finite(by) & finite(bz) & finite(bits_of(intensity[i]));
    const std::uint32_t away = non_zero(bx, by, bz);
    x[kept] = x[i];
    y[kept] = y[i];
    z[kept] = z[i];
    intensity[kept] = intensity[i];
    if constexpr (kWithRing) ring[kept] = ring[i];
    if constexpr (kWithTime) time[kept] = time[i];
    non_finite += ok ^ 1u;
    zero += ok & (away ^ 1u);
    kept += ok & away;
  }
  set_size(cloud, kept, kWithRing, kWithTime);
  stats.valid_points += kept - first;
  stats.non_finite += non_finite;
  stats.zero += zero;
}

}  // namespace

std::size_t grow_columns(PointCloud& cloud, std::size_t n, bool with_ring, bool with_time) {
  const std::size_t first = cloud.size();
  set_size(cloud, first + n, with_ring, with_time);
  return first;
}

void drop_invalid_points(PointCloud& cloud, std::size_t first, CloudStats& stats) {
  const std::size_t end = cloud.size();
  const float* x = cloud.x.data();
  const float* y = cloud.y.data();
  const float* z = cloud.z.data();
  const float* intensity = cloud.intensity.data();
  // Almost every block of a real scan is all valid: one vectorised scan proves it.
  std::size_t rejected = 0;
  for (std::size_t i = first; i < end; ++i) {
    const std::uint32_t bx = bits_of(x[i]), by = bits_of(y[i]), bz = bits_of(z[i]);
    const std::uint32_t ok =
        finite(bx) & finite(by) & finite(bz) & finite(bits_of(intensity[i])) & non_zero(bx, by, bz);
    rejected += ok ^ 1u;
  }
  if (rejected == 0) {
    stats.valid_points += end - first;
    return;
  }
  const bool with_ring = cloud.has_ring(), with_time = cloud.has_time();
  if (with_ring && with_time) return compact<true, true>(cloud, first, stats);
  if (with_ring) return compact<true, false>(cloud, first, stats);
  if (with_time) return compact<false, true>(cloud, first, stats);
  compact<false, false>(cloud, first, stats);
}

}  // namespace iilfm::io
