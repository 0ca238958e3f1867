#include "iilfm/preprocess.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "iilfm/square_pixels.hpp"

namespace iilfm {

namespace {

// Mean of the observed 8-neighbours for unobserved pixels with enough of them. Only the detector
// sees these values: no 3-D point is ever made from a filled pixel. Box filters of the masked
// intensity and of the mask give every pixel's neighbour sum and count in two vectorised passes.
void fill_holes(const cv::Mat& intensity, const cv::Mat& mask, int min_neighbours, cv::Mat& filled,
                cv::Mat& filled_mask) {
  cv::Mat observed, masked, sum, count;
  mask.convertTo(observed, CV_32F, 1.0 / 255.0);
  cv::multiply(intensity, observed, masked);
  cv::boxFilter(masked, sum, CV_32F, cv::Size(3, 3), cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  cv::boxFilter(observed, count, CV_32F, cv::Size(3, 3), cv::Point(-1, -1), false,
                cv::BORDER_CONSTANT);
  const cv::Mat fillable = (mask == 0) & (count >= static_cast<float>(min_neighbours) - 0.5f);
  intensity.copyTo(filled);
  cv::Mat mean;
  cv::divide(sum, cv::max(count, 1.0f), mean);
  mean.copyTo(filled, fillable);
  filled_mask = mask | fillable;
}

// Intensity that maps to gray 255: the 99th percentile of observed values, so a few
// retro-reflectors do not darken everything else. Every 4th pixel of every 2nd row is plenty for a
// percentile of a display scale and keeps this off the frame's critical path.
double robust_max(const cv::Mat& intensity, const cv::Mat& mask) {
  std::vector<float> values;
  values.reserve(static_cast<std::size_t>(intensity.total() / 8 + 1));
  auto sample = [&](int row_step, int col_step) {
    values.clear();
    for (int r = 0; r < intensity.rows; r += row_step) {
      const float* v = intensity.ptr<float>(r);
      const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
      for (int c = 0; c < intensity.cols; c += col_step)
        if (m[c]) values.push_back(v[c]);
    }
  };
  sample(2, 4);
  if (values.size() < 1000) sample(1, 1);  // sparse or small images: use every pixel
  if (values.empty()) return 1.0;
  const std::size_t k = (values.size() * 99) / 100;
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return std::max(1e-6, static_cast<double>(values[k]));
}

// Otsu's threshold over the observed gray values, returned in intensity units.
double otsu_threshold(const cv::Mat& gray, const cv::Mat& mask, double scale) {
  int histogram[256] = {};
  int total = 0;
  for (int r = 0; r < gray.rows; ++r) {
    const std::uint8_t* g = gray.ptr<std::uint8_t>(r);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < gray.cols; ++c)
      if (m[c]) {
        ++histogram[g[c]];
        ++total;
      }
  }
  double sum_all = 0;
  for (int i = 0; i < 256; ++i) sum_all += i * static_cast<double>(histogram[i]);
  double best = -1, best_t = 127.5, sum_below = 0;
  int below = 0;
  for (int t = 0; t < 255; ++t) {
    below += histogram[t];
    sum_below += t * static_cast<double>(histogram[t]);
    const int above = total - below;
    if (below == 0 || above == 0) continue;
    const double mean_below = sum_below / below, mean_above = (sum_all - sum_below) / above;
    const double between =
        static_cast<double>(below) * above * std::pow(mean_below - mean_above, 2);
    if (between > best) {
      best = between;
      best_t = t + 0.5;
    }
  }
  return best_t * scale / 255.0;
}

}  // namespace

void preprocess(const ProjectedImage& image, const PreprocessOptions& options,
                PreprocessedImage& out) {
  cv::Mat filled, filled_mask;
  if (options.fill_holes) {
    fill_holes(image.intensity, image.mask, options.fill_min_neighbours, filled, filled_mask);
    for (int pass = 1; pass < options.fill_passes; ++pass) {
      cv::Mat previous = filled, previous_mask = filled_mask;
      fill_holes(previous, previous_mask, options.fill_min_neighbours, filled, filled_mask);
    }
  } else {
    filled = image.intensity;
    filled_mask = image.mask;
  }

  if (options.square_pixels && needs_square_pixels(image.geometry)) {
    out.geometry = square_pixel_geometry(image.geometry);
    cv::Mat square, square_mask;
    resample_rows(filled, filled_mask, image.geometry, out.geometry, square, square_mask);
    filled = square;
    filled_mask = square_mask;
  } else {
    out.geometry = image.geometry;
  }

  filled_mask.copyTo(out.valid);
  out.intensity_scale = robust_max(image.intensity, image.mask);
  filled.convertTo(out.gray, CV_8U, 255.0 / out.intensity_scale);
  out.gray.setTo(options.unobserved_value, filled_mask == 0);

  out.threshold = options.threshold ? *options.threshold
                                    : otsu_threshold(out.gray, filled_mask, out.intensity_scale);
  if (options.binarize) {
    cv::Mat above = filled > out.threshold;  // 255 where brighter than the threshold
    out.detect.create(filled.size(), CV_8U);
    out.detect.setTo(0);
    out.detect.setTo(255, above & filled_mask);
    out.detect.setTo(options.unobserved_value, filled_mask == 0);
  } else {
    out.gray.copyTo(out.detect);
  }
  if (options.blur_sigma > 0) {
    cv::GaussianBlur(out.detect, out.detect, cv::Size(0, 0), options.blur_sigma);
  }
}

}  // namespace iilfm
