#include "iilfm/square_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "cpu_clones.hpp"

namespace iilfm {

namespace {

// One output row: `near`'s value where it was observed, else `far`'s, else unobserved (0). Loads
// before selects, so the loop vectorises.
IILFM_AVX2_CLONES void merge_rows(const float* __restrict near,
                                  const std::uint8_t* __restrict near_valid,
                                  const float* __restrict far,
                                  const std::uint8_t* __restrict far_valid, int width,
                                  float* __restrict out, std::uint8_t* __restrict out_valid) {
  for (int c = 0; c < width; ++c) {
    const float a = near[c], b = far[c];
    const std::uint8_t has_a = near_valid[c], has_b = far_valid[c];
    const float b_or_zero = has_b ? b : 0.0f;
    out[c] = has_a ? a : b_or_zero;
    out_valid[c] = (has_a | has_b) ? 255 : 0;
  }
}

}  // namespace

bool needs_square_pixels(const ImageGeometry& g) {
  if (g.height <= 1) return false;
  double coarsest = g.res_v;
  for (std::size_t r = 1; r < g.row_elevation.size(); ++r)
    coarsest = std::max(coarsest, g.row_elevation[r - 1] - g.row_elevation[r]);
  return coarsest > kSquarePixelRatio * g.res_h;
}

ImageGeometry square_pixel_geometry(const ImageGeometry& g) {
  if (!needs_square_pixels(g)) return g;
  double step = g.res_h;
  for (std::size_t r = 1; r < g.row_elevation.size(); ++r)
    step = std::min(step, g.row_elevation[r - 1] - g.row_elevation[r]);
  step = std::max(step, 0.5 * g.res_h);  // two rings a hair apart must not blow the image up
  const double top = g.elevation_of_v(0), bottom = g.elevation_of_v(g.height - 1);
  ImageGeometry out;
  out.width = g.width;
  out.res_h = g.res_h;
  out.u0 = g.u0;
  out.res_v = step;
  out.v0 = top / step;
  out.height = static_cast<int>(std::lround((top - bottom) / step)) + 1;
  return out;
}

void resample_rows(const cv::Mat& image, const cv::Mat& valid, const ImageGeometry& from,
                   const ImageGeometry& to, cv::Mat& out_image, cv::Mat& out_valid,
                   std::vector<std::uint8_t>* repeats_row_above, bool copy_repeated_values) {
  copy_repeated_values |= repeats_row_above == nullptr;
  out_image.create(to.height, to.width, CV_32F);
  if (repeats_row_above) repeats_row_above->assign(static_cast<std::size_t>(to.height), 0);
  out_valid.create(to.height, to.width, CV_8U);
  const int last = from.height - 1;
  int previous_near = -1, previous_far = -1;
  for (int r = 0; r < to.height; ++r) {
    const double v =
        std::clamp(from.v_of_elevation(to.elevation_of_v(r)), 0.0, static_cast<double>(last));
    const int r0 = std::min(static_cast<int>(v), std::max(last - 1, 0));
    const int r1 = std::min(r0 + 1, last);
    // The nearer row's value where it was observed, else the farther one's.
    const bool first_nearer = static_cast<float>(v - r0) < 0.5f;
    const int near = first_nearer ? r0 : r1, far = first_nearer ? r1 : r0;
    float* o = out_image.ptr<float>(r);
    std::uint8_t* vo = out_valid.ptr<std::uint8_t>(r);
    if (near == previous_near && far == previous_far) {  // most rows repeat the one above
      if (repeats_row_above) (*repeats_row_above)[static_cast<std::size_t>(r)] = 1;
      if (copy_repeated_values)
        std::memcpy(o, out_image.ptr<float>(r - 1),
                    sizeof(float) * static_cast<std::size_t>(to.width));
      std::memcpy(vo, out_valid.ptr<std::uint8_t>(r - 1), static_cast<std::size_t>(to.width));
    } else {
      merge_rows(image.ptr<float>(near), valid.ptr<std::uint8_t>(near), image.ptr<float>(far),
                 valid.ptr<std::uint8_t>(far), to.width, o, vo);
    }
    previous_near = near;
    previous_far = far;
  }
}

}  // namespace iilfm
