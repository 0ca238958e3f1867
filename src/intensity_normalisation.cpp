#include "iilfm/intensity_normalisation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "iilfm/projection.hpp"

namespace iilfm {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Mean range of the observed pixels of the window around (row, col), their centroid (column,
// row), and whether the window holds any.
struct WindowMean {
  const cv::Mat& sum;
  const cv::Mat& count;
  const cv::Mat& col_sum;
  const cv::Mat& row_sum;
  struct Value {
    float range = 0, col = 0, row = 0;
    bool valid = false;
  };
  Value at(int row, int col) const {
    Value v;
    const float n = count.at<float>(row, col);
    v.valid = n > 0.5f;
    if (!v.valid) return v;
    v.range = sum.at<float>(row, col) / n;
    v.col = col_sum.at<float>(row, col) / n;
    v.row = row_sum.at<float>(row, col) / n;
    return v;
  }
};

}  // namespace

const char* to_string(IntensityNormalisation mode) {
  switch (mode) {
    case IntensityNormalisation::kRange:
      return "range";
    case IntensityNormalisation::kRangeIncidence:
      return "range-incidence";
    case IntensityNormalisation::kNone:
      break;
  }
  return "none";
}

// The surface r(azimuth, elevation) seen in the range image has, at a pixel, the normal whose
// angle to the ray satisfies
//   1 / cos^2 = 1 + (dr/daz / (r cos(el)))^2 + (dr/del / r)^2,
// so the range image's slopes give the incidence without making 3-D points. Each slope is the
// difference of the mean range over the windows either side (half-width a columns, b rows) over
// the distance between those windows' centroids of observed pixels (holes and the image border
// move them), which averages the range noise of the window's points; a side without observed
// pixels is replaced by the window around the pixel itself.
void estimate_cos_incidence(const ProjectedImage& image, const NormalisationOptions& options,
                            NormalisationBuffers& work, cv::Mat& cos_incidence) {
  const ImageGeometry& g = image.geometry;
  const int rows = image.range.rows, cols = image.range.cols;
  cos_incidence.create(rows, cols, CV_32F);
  cos_incidence.setTo(1.0f);
  if (rows == 0 || cols == 0 || !(g.res_h > 0) || !(g.res_v > 0)) return;
  const double half = options.normal_half_window_deg * kDegToRad;
  const int a = std::max(1, static_cast<int>(std::lround(half / g.res_h)));
  const int b = std::max(1, static_cast<int>(std::lround(half / g.res_v)));
  image.mask.convertTo(work.weight, CV_32F, 1.0 / 255.0);
  work.weighted_col.create(rows, cols, CV_32F);
  work.weighted_row.create(rows, cols, CV_32F);
  for (int r = 0; r < rows; ++r) {
    const float* __restrict w = work.weight.ptr<float>(r);
    float* __restrict wc = work.weighted_col.ptr<float>(r);
    float* __restrict wr = work.weighted_row.ptr<float>(r);
    for (int c = 0; c < cols; ++c) {
      wc[c] = w[c] * static_cast<float>(c);
      wr[c] = w[c] * static_cast<float>(r);
    }
  }
  // The range image is 0 where unobserved, so its window sum is the observed pixels' sum. Column
  // and row sums are sums of integers below 2^24: exact in float.
  const cv::Size window(2 * a + 1, 2 * b + 1);
  auto box = [&](const cv::Mat& in, cv::Mat& sum) {
    cv::boxFilter(in, sum, CV_32F, window, cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  };
  box(image.range, work.range_sum);
  box(work.weight, work.weight_sum);
  box(work.weighted_col, work.col_sum);
  box(work.weighted_row, work.row_sum);
  const WindowMean mean{work.range_sum, work.weight_sum, work.col_sum, work.row_sum};
  const float max_gain_sq =
      static_cast<float>(1.0 / (options.min_cos_incidence * options.min_cos_incidence));

  for (int r = 0; r < rows; ++r) {
    const int up = std::max(0, r - b), down = std::min(rows - 1, r + b);
    const double el = g.elevation_of_v(r);
    // Elevation per row about this row (ring rows are not evenly spaced).
    const double per_row =
        down > up ? std::abs(g.elevation_of_v(up) - g.elevation_of_v(down)) / (down - up) : g.res_v;
    const float per_az = static_cast<float>(1.0 / (g.res_h * std::max(0.05, std::cos(el))));
    const float per_el = static_cast<float>(1.0 / per_row);
    const std::uint8_t* m = image.mask.ptr<std::uint8_t>(r);
    float* out = cos_incidence.ptr<float>(r);
    for (int c = 0; c < cols; ++c) {
      if (!m[c]) continue;
      const WindowMean::Value centre = mean.at(r, c);
      if (!centre.valid || !(centre.range > 0)) continue;
      WindowMean::Value left = mean.at(r, std::max(0, c - a));
      WindowMean::Value right = mean.at(r, std::min(cols - 1, c + a));
      WindowMean::Value above = mean.at(up, c), below = mean.at(down, c);
      if (!left.valid) left = centre;
      if (!right.valid) right = centre;
      if (!above.valid) above = centre;
      if (!below.valid) below = centre;
      const float d_col = right.col - left.col, d_row = below.row - above.row;
      const float g_az =
          d_col > 0.5f ? (right.range - left.range) / d_col * per_az / centre.range : 0.0f;
      const float g_el =
          d_row > 0.5f ? (above.range - below.range) / d_row * per_el / centre.range : 0.0f;
      // A slope steeper than the clamp allows is a depth edge inside the window (a board in
      // front of a far wall), not one surface: no correction there, or the edge would glow.
      const float gain_sq = 1.0f + g_az * g_az + g_el * g_el;
      out[c] = gain_sq <= max_gain_sq ? 1.0f / std::sqrt(gain_sq) : 1.0f;
    }
  }
}

void normalise_intensity(const ProjectedImage& image, const NormalisationOptions& options,
                         NormalisationBuffers& work, cv::Mat& out) {
  if (options.mode == IntensityNormalisation::kNone) return;
  const int rows = image.intensity.rows, cols = image.intensity.cols;
  out.create(rows, cols, CV_32F);
  const float per_ref_sq = static_cast<float>(1.0 / (options.reference_m * options.reference_m));
  // Range only: one pass that vectorises (the range is 0 where unobserved, so is the product).
  for (int r = 0; r < rows; ++r) {
    const float* __restrict i = image.intensity.ptr<float>(r);
    const float* __restrict d = image.range.ptr<float>(r);
    float* __restrict o = out.ptr<float>(r);
    for (int c = 0; c < cols; ++c) o[c] = i[c] * (d[c] * d[c] * per_ref_sq);
  }
  if (options.mode != IntensityNormalisation::kRangeIncidence) return;
  estimate_cos_incidence(image, options, work, work.cos_incidence);
  cv::divide(out, work.cos_incidence, out);
}

}  // namespace iilfm
