// The projection's per-point passes, shared by the one-shot and the sliding-window projectors so
// that both put every point in exactly the same pixel.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fast_math.hpp"
#include "iilfm/projection.hpp"

namespace iilfm::detail {

// Pass 1 over contiguous or strided columns: spherical coordinates (paper Eq. 1). No reduction
// in the loop, so GCC vectorises it for contiguous columns.
template <typename Column>
inline void spherical_coordinates(const Column& xs, const Column& ys, const Column& zs,
                                  std::size_t n, float* __restrict azimuth,
                                  float* __restrict elevation, float* __restrict range) {
  for (std::size_t i = 0; i < n; ++i) {
    const float x = xs[i], y = ys[i], z = zs[i];
    const float horizontal_sq = x * x + y * y;
    azimuth[i] = detail::fast_atan2(y, x);
    elevation[i] = detail::fast_atan2(z, std::sqrt(horizontal_sq));
    range[i] = std::sqrt(horizontal_sq + z * z);
  }
}

// Pass 1 over contiguous columns, vectorised (src/projection_passes.cpp: 8 lanes where the CPU
// has AVX2, 4 otherwise; the same operations in the same order, so the same results).
void spherical_coordinates_contiguous(const float* x, const float* y, const float* z, std::size_t n,
                                      float* azimuth, float* elevation, float* range);

// Spherical coordinates of any point view, contiguous columns on the vectorised path.
inline void spherical_coordinates(const PointView& cloud, float* azimuth, float* elevation,
                                  float* range) {
  if (cloud.x.stride == 1 && cloud.y.stride == 1 && cloud.z.stride == 1) {
    spherical_coordinates_contiguous(cloud.x.data, cloud.y.data, cloud.z.data, cloud.size(),
                                     azimuth, elevation, range);
  } else {
    spherical_coordinates(cloud.x, cloud.y, cloud.z, cloud.size(), azimuth, elevation, range);
  }
}

// Pass 2 for uniform rows: each point's pixel (row * row_stride + column, -1 outside the image).
// Branch-free, so it vectorises (like pass 1, 8 lanes with AVX2). Returns the points outside.
std::size_t pixels_of_points(const ImageGeometry& g, std::int32_t row_stride, const float* azimuth,
                             const float* elevation, const float* range, std::size_t n,
                             std::int32_t* pixel);

// Pass 2 for ring rows from the ring field (contiguous; SphericalProjector copies a strided one):
// each point's pixel (row_of_ring[ring] * row_stride + column, -1 outside the image or on a ring
// without a row). Branch-free, so it vectorises (the row a gather).
void ring_pixels_of_points(const ImageGeometry& g, std::int32_t row_stride,
                           const std::int32_t* row_of_ring, std::size_t ring_ids,
                           const std::uint16_t* ring, const float* azimuth, const float* range,
                           std::size_t n, std::int32_t* pixel);

}  // namespace iilfm::detail
