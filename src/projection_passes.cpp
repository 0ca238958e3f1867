#include "projection_passes.hpp"

#include <algorithm>

// Both passes are cloned for AVX2 (twice the lanes of the SSE2 baseline).
#include "cpu_clones.hpp"

namespace iilfm::detail {

namespace {
struct Contiguous {
  const float* __restrict data;
  float operator[](std::size_t i) const { return data[i]; }
};
}  // namespace

IILFM_AVX2_CLONES void spherical_coordinates_contiguous(const float* x, const float* y,
                                                        const float* z, std::size_t n,
                                                        float* azimuth, float* elevation,
                                                        float* range) {
  spherical_coordinates(Contiguous{x}, Contiguous{y}, Contiguous{z}, n, azimuth, elevation, range);
}

IILFM_AVX2_CLONES std::size_t pixels_of_points(const ImageGeometry& g, std::int32_t row_stride,
                                               const float* __restrict azimuth,
                                               const float* __restrict elevation,
                                               const float* __restrict range, std::size_t n,
                                               std::int32_t* __restrict pixel) {
  const float u0 = static_cast<float>(g.u0), v0 = static_cast<float>(g.v0);
  const float inv_res_h = static_cast<float>(1 / g.res_h),
              inv_res_v = static_cast<float>(1 / g.res_v);
  const float u_end = static_cast<float>(g.width) - 0.5f,
              v_end = static_cast<float>(g.height) - 0.5f;
  const float wrap = static_cast<float>(g.wrapping_columns());
  std::size_t outside = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float unwrapped = u0 - azimuth[i] * inv_res_h, v = v0 - elevation[i] * inv_res_v;
    // Past a full circle's last column: the first one's (a product, not a select, to vectorise).
    const float u = unwrapped - wrap * static_cast<float>(unwrapped >= u_end);
    // Bitwise, not short-circuit: no branch in the loop.
    const bool in = (range[i] > 0) & (u >= -0.5f) & (v >= -0.5f) & (u < u_end) & (v < v_end);
    // Inside, both are >= -0.5, so truncating x + 0.5 rounds to nearest without a libm call.
    // Clamped rather than selected: a select here kept GCC from vectorising the AVX2 clone (it
    // turns the int round trip into a rounding instruction and gives up on the branch). The
    // operand order sends NaN to 0, so the conversion is always defined.
    const float uc = std::min(u_end, std::max(0.0f, u + 0.5f)),
                vc = std::min(v_end, std::max(0.0f, v + 0.5f));
    const std::int32_t col = static_cast<std::int32_t>(uc), row = static_cast<std::int32_t>(vc);
    pixel[i] = in ? row * row_stride + col : -1;
    outside += in ? 0 : 1;
  }
  return outside;
}

IILFM_AVX2_CLONES void ring_pixels_of_points(
    const ImageGeometry& g, std::int32_t row_stride, const std::int32_t* __restrict row_of_ring,
    std::size_t ring_ids, const std::uint16_t* __restrict ring, const float* __restrict azimuth,
    const float* __restrict range, std::size_t n, std::int32_t* __restrict pixel) {
  const float u0 = static_cast<float>(g.u0), inv_res_h = static_cast<float>(1 / g.res_h);
  const std::int32_t width = g.width;
  const float u_end = static_cast<float>(width) - 0.5f, width_f = static_cast<float>(width);
  const float wrap = static_cast<float>(g.wrapping_columns());
  const auto last_ring = static_cast<std::int32_t>(ring_ids) - 1;
  for (std::size_t i = 0; i < n; ++i) {
    const float unwrapped = u0 - azimuth[i] * inv_res_h;
    const float u = unwrapped - wrap * static_cast<float>(unwrapped >= u_end);  // as above
    // As pixels_of_points: truncating u + 0.5 rounds to nearest inside the image, the clamp
    // (NaN to 0) keeps the conversion defined. Clamped to the width, not below it, so a sum
    // that rounds up to it still falls outside.
    const auto col = static_cast<std::int32_t>(std::min(width_f, std::max(0.0f, u + 0.5f)));
    // A ring beyond the table reads its last entry and is then dropped (a clamp, not a branch).
    const std::int32_t id = ring[i];
    const std::int32_t row = row_of_ring[std::min(id, last_ring)];
    const bool in = (range[i] > 0) & (u >= -0.5f) & (u < u_end) & (col < width) &
                    (id <= last_ring) & (row >= 0);
    pixel[i] = in ? row * row_stride + col : -1;
  }
}

}  // namespace iilfm::detail
