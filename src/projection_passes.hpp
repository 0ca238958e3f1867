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

struct Contiguous {
  const float* __restrict data;
  float operator[](std::size_t i) const { return data[i]; }
};

// Spherical coordinates of any point view, contiguous columns on the vectorised path.
inline void spherical_coordinates(const PointView& cloud, float* azimuth, float* elevation,
                                  float* range) {
  if (cloud.x.stride == 1 && cloud.y.stride == 1 && cloud.z.stride == 1) {
    spherical_coordinates(Contiguous{cloud.x.data}, Contiguous{cloud.y.data},
                          Contiguous{cloud.z.data}, cloud.size(), azimuth, elevation, range);
  } else {
    spherical_coordinates(cloud.x, cloud.y, cloud.z, cloud.size(), azimuth, elevation, range);
  }
}

// Pass 2 for uniform rows: each point's pixel (row-major index, -1 outside the image) and squared
// distance to the pixel centre. Branch-free, so it vectorises. Returns the points outside.
inline std::size_t pixels_of_points(const ImageGeometry& g, const float* __restrict azimuth,
                                    const float* __restrict elevation,
                                    const float* __restrict range, std::size_t n,
                                    std::int32_t* __restrict pixel, float* __restrict offset) {
  const float u0 = static_cast<float>(g.u0), v0 = static_cast<float>(g.v0);
  const float inv_res_h = static_cast<float>(1 / g.res_h),
              inv_res_v = static_cast<float>(1 / g.res_v);
  const float u_end = static_cast<float>(g.width) - 0.5f,
              v_end = static_cast<float>(g.height) - 0.5f;
  const std::int32_t width = g.width;
  std::size_t outside = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float u = u0 - azimuth[i] * inv_res_h, v = v0 - elevation[i] * inv_res_v;
    // Bitwise, not short-circuit: no branch in the loop.
    const bool in = (range[i] > 0) & (u >= -0.5f) & (v >= -0.5f) & (u < u_end) & (v < v_end);
    // Inside, both are >= -0.5, so truncating x + 0.5 rounds to nearest without a libm call.
    const float uc = in ? u + 0.5f : 0.5f, vc = in ? v + 0.5f : 0.5f;
    const std::int32_t col = static_cast<std::int32_t>(uc), row = static_cast<std::int32_t>(vc);
    const float du = u - static_cast<float>(col), dv = v - static_cast<float>(row);
    pixel[i] = in ? row * width + col : -1;
    offset[i] = du * du + dv * dv;
    outside += in ? 0 : 1;
  }
  return outside;
}

}  // namespace iilfm::detail
