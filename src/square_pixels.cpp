#include "iilfm/square_pixels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace iilfm {

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
                   const ImageGeometry& to, cv::Mat& out_image, cv::Mat& out_valid) {
  out_image.create(to.height, to.width, CV_32F);
  out_valid.create(to.height, to.width, CV_8U);
  const int last = from.height - 1;
  for (int r = 0; r < to.height; ++r) {
    const double v =
        std::clamp(from.v_of_elevation(to.elevation_of_v(r)), 0.0, static_cast<double>(last));
    const int r0 = std::min(static_cast<int>(v), std::max(last - 1, 0));
    const int r1 = std::min(r0 + 1, last);
    const float w = static_cast<float>(v - r0);
    const float* a = image.ptr<float>(r0);
    const float* b = image.ptr<float>(r1);
    const std::uint8_t* va = valid.ptr<std::uint8_t>(r0);
    const std::uint8_t* vb = valid.ptr<std::uint8_t>(r1);
    float* o = out_image.ptr<float>(r);
    std::uint8_t* vo = out_valid.ptr<std::uint8_t>(r);
    for (int c = 0; c < to.width; ++c) {
      if (va[c] && vb[c]) {
        o[c] = w < 0.5f ? a[c] : b[c];
        vo[c] = 255;
      } else if (va[c] || vb[c]) {
        o[c] = va[c] ? a[c] : b[c];
        vo[c] = 255;
      } else {
        o[c] = 0;
        vo[c] = 0;
      }
    }
  }
}

}  // namespace iilfm
