// The passes of the robust plane fit over its points (plane_lift.cpp), on coordinates held in
// separate arrays so that each pass vectorises: a coplanar wall gives the fit ~10^5 points, read
// several times per marker. Sums run in four interleaved lanes, added in a fixed order at the end,
// so the result is the same whatever vector width the CPU has.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm::detail {

// An allocator whose vectors leave new elements of a resize uninitialised: the fit's buffers are
// sized for the most points a pass can write and then trimmed, and zeroing megabytes that are
// overwritten at once cost as much as a pass.
template <typename T>
struct UninitialisedAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitialisedAllocator<U>;
  };
  UninitialisedAllocator() = default;
  template <typename U>
  UninitialisedAllocator(const UninitialisedAllocator<U>&) noexcept {}
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;  // default-initialised: no value for a double
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <typename T>
using Buffer = std::vector<T, UninitialisedAllocator<T>>;

// A fit's points, one array per coordinate. Floats: a cloud's points are floats, so a
// single-point pixel's coordinates are exact and a several-point pixel's (its mean range along the
// pixel's ray) within 0.3 um at 5 m; every pass reads them as doubles and sums in doubles. Half
// the bytes of doubles, so a coplanar wall's 10^5 points stay in L2 between passes.
struct FitPoints {
  Buffer<float> x, y, z;

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n) {
    x.resize(n);
    y.resize(n);
    z.resize(n);
  }
};

// The points at `range[k]` along the rays of elevation (cos_el, sin_el) and azimuth (cos_az[k],
// sin_az[k]), k < n, as floats: x = cos_el cos_az range, y = cos_el sin_az range, z = sin_el range
// (each product in that order).
void ray_points(double cos_el, double sin_el, const double* cos_az, const double* sin_az,
                const float* range, std::size_t n, float* x, float* y, float* z);

// The points whose label is within [lo, hi], in order, into `to`.
void keep_labelled(const FitPoints& from, const std::uint8_t* label, std::uint8_t lo,
                   std::uint8_t hi, FitPoints& to);

// Appends to `to`, in order, the points whose label is within [lo, hi] and whose value is at most
// `band`.
void append_labelled_within(const FitPoints& from, const std::uint8_t* label, std::uint8_t lo,
                            std::uint8_t hi, const double* value, double band, FitPoints& to);

// Sums of the coordinates about `ref` and of their products.
struct CoordinateSums {
  double n = 0, x = 0, y = 0, z = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
};
CoordinateSums coordinate_sums(const FitPoints& p, const Vec3& ref);
// The same over the points [begin, end).
CoordinateSums coordinate_sums(const FitPoints& p, const Vec3& ref, std::size_t begin,
                               std::size_t end);

// |normal . p - d| of every point into `residual` (p.size() values).
void plane_residuals(const FitPoints& p, const Vec3& normal, double d, double* residual);

// The points whose residual is at most `band`, in order, into `to`; returns how many.
std::size_t keep_within(const FitPoints& from, const double* residual, double band, FitPoints& to);

// For a plane's uncertainty: the residuals' squares, each point's in-plane coordinates (x1, x2
// along axis1, axis2 about `centre`) squared and weighted by them, and the coordinates' extent.
struct SpreadSums {
  double sum_sq = 0, s1 = 0, s2 = 0, h1 = 0, h2 = 0;
  double min1 = 1e300, max1 = -1e300, min2 = 1e300, max2 = -1e300;
};
SpreadSums spread_sums(const FitPoints& p, const Vec3& normal, double d, const Vec3& centre,
                       const Vec3& axis1, const Vec3& axis2);

// Each point's patch of a grid x grid split of the plane along axis1 and axis2 about `centre`
// (extent: x1 from, to, x2 from, to), as b1 * grid + b2, clamped to the grid.
void grid_patches(const FitPoints& p, const Vec3& centre, const Vec3& axis1, const Vec3& axis2,
                  const double extent[4], int grid, std::int32_t* patch);

// The value of rank `rank` (0-based) among v[0, n): what std::nth_element would put there, found by
// counting the values into bins of their range and selecting only within the bin that holds the
// rank (bins are monotone in the value, so the result is exact). A fit's residuals are all
// finite; a NaN among them gives an unspecified value, as nth_element would. n > rank.
double value_of_rank(const double* v, std::size_t n, std::size_t rank);

}  // namespace iilfm::detail
