#include "iilfm/preprocess.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "cpu_clones.hpp"
#include "hole_classes.hpp"
#include "iilfm/square_pixels.hpp"

namespace iilfm {

namespace {

// Mean of the observed 8-neighbours for unobserved pixels with at least `min_neighbours` of them.
// Only the detector sees these values: no 3-D point is ever made from a filled pixel. One pass
// over the rows: each row's observed values and observed count once (kept for the next two rows),
// their 3-row column sums, then 3-column sums of those. The loops vectorise (checked with
// -fopt-info-vec); the per-pixel one selects rather than blends, since 0 x an infinite mean would
// be NaN.
IILFM_AVX2_CLONES void fill_holes(const cv::Mat& intensity, const cv::Mat& mask, int min_neighbours,
                                  cv::Mat& filled, cv::Mat& filled_mask) {
  const int rows = intensity.rows, cols = intensity.cols;
  filled.create(rows, cols, CV_32F);
  filled_mask.create(rows, cols, CV_8U);
  // Rows padded by one zero column on each side: three rows' observed values and counts (row r in
  // slot r % 3) and a fourth of zeros for the rows beyond the image.
  const std::size_t padded = static_cast<std::size_t>(cols) + 2;
  thread_local std::vector<float> row_values, row_counts, value_sum, count_sum;
  row_values.assign(4 * padded, 0.0f);
  row_counts.assign(4 * padded, 0.0f);
  value_sum.resize(padded);
  count_sum.resize(padded);
  const auto load_row = [&](int r) {
    const std::size_t slot = static_cast<std::size_t>(r % 3) * padded + 1;
    float* __restrict vs = row_values.data() + slot;
    float* __restrict cs = row_counts.data() + slot;
    const float* __restrict v = intensity.ptr<float>(r);
    const std::uint8_t* __restrict m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      const float observed = m[c] ? 1.0f : 0.0f;
      vs[c] = v[c] * observed;
      cs[c] = observed;
    }
  };
  // Row r's slot (r % 3), or the zero row beyond the image.
  const auto slot_of = [&](int r) -> std::size_t {
    return r < 0 || r >= rows ? 3 : static_cast<std::size_t>(r % 3);
  };
  const float needed = static_cast<float>(min_neighbours) - 0.5f;
  if (rows > 0) load_row(0);
  for (int r = 0; r < rows; ++r) {
    if (r + 1 < rows) load_row(r + 1);  // into the slot of row r - 2, no longer needed
    // Each column's 3-row sums, added top to bottom as a running sum from zero would (the same
    // floats). Two loops: GCC vectorises neither when one holds both sums.
    const std::size_t s0 = slot_of(r - 1) * padded, s1 = slot_of(r) * padded,
                      s2 = slot_of(r + 1) * padded;
    float* __restrict vs = value_sum.data();
    float* __restrict cs = count_sum.data();
    {
      const float* __restrict a = row_values.data() + s0;
      const float* __restrict b = row_values.data() + s1;
      const float* __restrict c = row_values.data() + s2;
      for (int k = 0; k < cols + 2; ++k) vs[k] = a[k] + b[k] + c[k];
    }
    {
      const float* __restrict a = row_counts.data() + s0;
      const float* __restrict b = row_counts.data() + s1;
      const float* __restrict c = row_counts.data() + s2;
      for (int k = 0; k < cols + 2; ++k) cs[k] = a[k] + b[k] + c[k];
    }
    const float* __restrict v = intensity.ptr<float>(r);
    const std::uint8_t* __restrict m = mask.ptr<std::uint8_t>(r);
    float* __restrict out = filled.ptr<float>(r);
    std::uint8_t* __restrict out_mask = filled_mask.ptr<std::uint8_t>(r);
    // Every value is loaded before the selects, so the loop has no conditional load and
    // vectorises (masks hold 0 or 255). vs[k] is the sum of image column k - 1.
    for (int c = 0; c < cols; ++c) {
      const float value = v[c];
      const std::uint8_t observed = m[c];
      const float sum = vs[c] + vs[c + 1] + vs[c + 2];
      const float count = cs[c] + cs[c + 1] + cs[c + 2];
      const float mean = sum / std::max(count, 1.0f);
      const std::uint8_t fillable = count >= needed ? 255 : 0;
      // Selects, not a blend: 0 * an infinite mean would be NaN.
      const float fill = fillable ? mean : 0.0f;
      out[c] = observed ? value : fill;
      out_mask[c] = observed | fillable;
    }
  }
}

// Intensity that maps to gray 255: the 99th percentile of observed values, so a few
// retro-reflectors do not darken everything else. A grid of at most about 16k pixels (every 4th
// pixel of every 2nd row, sparser on large images) is plenty for a percentile of a display scale
// (its rank within 0.2 % at two standard errors) and keeps the selection off the frame's critical
// path: 74k values of a Mid-40 image took 0.4 ms.
double robust_max(const cv::Mat& intensity, const cv::Mat& mask) {
  constexpr double kMaxSampled = 16384;
  thread_local std::vector<float> values;  // reused: no allocation once warm
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
  // Denser grids while too few observed values were sampled (a sparse image). `values` is
  // thread-local: cleared first, so no earlier image's values count.
  values.clear();
  const double sparser = std::sqrt(static_cast<double>(intensity.total()) / 8 / kMaxSampled);
  if (sparser > 1)
    sample(static_cast<int>(std::ceil(2 * sparser)), static_cast<int>(std::ceil(4 * sparser)));
  if (values.size() < 1000) sample(2, 4);
  if (values.size() < 1000) sample(1, 1);  // sparse or small images: use every pixel
  if (values.empty()) return 1.0;
  const std::size_t k = (values.size() * 99) / 100;
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return std::max(1e-6, static_cast<double>(values[k]));
}

// Otsu's threshold over the observed gray values, returned in intensity units. A row that
// repeats the one above (`repeats_row_above`) is counted with it: its row's count goes up by one.
double otsu_threshold(const cv::Mat& gray, const cv::Mat& mask,
                      const std::vector<std::uint8_t>& repeats_row_above, double scale) {
  int histogram[256] = {};
  int total = 0;
  for (int r = 0; r < gray.rows;) {
    int copies = 1;
    while (r + copies < gray.rows && repeats_row_above[static_cast<std::size_t>(r + copies)])
      ++copies;
    const std::uint8_t* g = gray.ptr<std::uint8_t>(r);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < gray.cols; ++c)
      if (m[c]) {
        histogram[g[c]] += copies;
        total += copies;
      }
    r += copies;
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

// 255 where brighter than the valid pixels' mean around it; where the window is nearly flat (a
// wall, the sky), where brighter than the global threshold.
cv::Mat above_local_mean(const cv::Mat& filled, const cv::Mat& valid, double global_threshold,
                         double scale, const PreprocessOptions& options) {
  const int w = std::max(3, options.local_window | 1);
  cv::Mat weight, values, squares, sum, sum_sq, count;
  valid.convertTo(weight, CV_32F, 1.0 / 255.0);
  cv::multiply(filled, weight, values);
  cv::multiply(values, filled, squares);
  const cv::Size window(w, w);
  cv::boxFilter(values, sum, CV_32F, window, cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  cv::boxFilter(squares, sum_sq, CV_32F, window, cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  cv::boxFilter(weight, count, CV_32F, window, cv::Point(-1, -1), false, cv::BORDER_CONSTANT);
  count = cv::max(count, 1.0f);
  cv::Mat mean, mean_sq, variance;
  cv::divide(sum, count, mean);
  cv::divide(sum_sq, count, mean_sq);
  cv::subtract(mean_sq, mean.mul(mean), variance);
  const double min_spread = options.local_min_contrast * scale;
  cv::Mat contrasted = variance > static_cast<float>(min_spread * min_spread);
  cv::Mat local = filled > mean, global = filled > global_threshold;
  cv::Mat above;
  global.copyTo(above);
  local.copyTo(above, contrasted);
  return above;
}

// 8-bit gray for display and for Otsu: intensity scaled so `scale` maps to 255; pixels still
// unobserved get `unobserved`. A row that repeats the one above is copied.
IILFM_AVX2_CLONES void to_gray(const cv::Mat& filled, const cv::Mat& valid,
                               const std::vector<std::uint8_t>& repeats_row_above, double scale,
                               int unobserved, cv::Mat& gray) {
  gray.create(filled.size(), CV_8U);
  const float factor = static_cast<float>(255.0 / scale);
  const std::uint8_t hole = cv::saturate_cast<std::uint8_t>(unobserved);
  const int cols = filled.cols;  // a local: the byte stores below could alias the Mat's fields
  for (int r = 0; r < filled.rows; ++r) {
    std::uint8_t* __restrict g = gray.ptr<std::uint8_t>(r);
    if (repeats_row_above[static_cast<std::size_t>(r)]) {
      std::memcpy(g, gray.ptr<std::uint8_t>(r - 1), static_cast<std::size_t>(cols));
      continue;
    }
    const float* __restrict v = filled.ptr<float>(r);
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      // max(0, level) takes 0 for a NaN (an overflowed sum): never an undefined cast.
      const float level = v[c] * factor + 0.5f;
      const float clamped = std::min(255.0f, std::max(0.0f, level));
      // Through int32: GCC converts float to unsigned bytes element by element.
      const auto value = static_cast<std::uint8_t>(static_cast<std::int32_t>(clamped));
      g[c] = static_cast<std::uint8_t>((value & m[c]) | (hole & ~m[c]));  // masks hold 0 or 255
    }
  }
}

// The naive global threshold: 255 where brighter than `threshold`, 0 where not, `unobserved`
// where no value is known. A row that repeats the one above is copied.
IILFM_AVX2_CLONES void binarize(const cv::Mat& filled, const cv::Mat& valid,
                                const std::vector<std::uint8_t>& repeats_row_above,
                                double threshold, int unobserved, cv::Mat& detect) {
  detect.create(filled.size(), CV_8U);
  const float t = static_cast<float>(threshold);
  const std::uint8_t hole = cv::saturate_cast<std::uint8_t>(unobserved);
  const int cols = filled.cols;
  for (int r = 0; r < filled.rows; ++r) {
    std::uint8_t* __restrict d = detect.ptr<std::uint8_t>(r);
    if (repeats_row_above[static_cast<std::size_t>(r)]) {
      std::memcpy(d, detect.ptr<std::uint8_t>(r - 1), static_cast<std::size_t>(cols));
      continue;
    }
    const float* __restrict v = filled.ptr<float>(r);
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      const std::uint8_t level = v[c] > t ? 255 : 0;
      d[c] = static_cast<std::uint8_t>((level & m[c]) | (hole & ~m[c]));  // masks hold 0 or 255
    }
  }
}

}  // namespace

void preprocess(const ProjectedImage& image, const PreprocessOptions& options,
                PreprocessedImage& out) {
  const cv::Mat* source = &image.intensity;
  if (options.normalise.mode != IntensityNormalisation::kNone) {
    normalise_intensity(image, options.normalise, out.normalise_work, out.normalised);
    source = &out.normalised;
  }
  // Hole filling alternates between two reused buffer pairs (a pass reads the previous one).
  const cv::Mat* values = source;
  const cv::Mat* mask = &image.mask;
  for (int pass = 0; options.fill_holes && pass < std::max(1, options.fill_passes); ++pass) {
    PreprocessedImage::Buffers& into = out.work[pass % 2];
    fill_holes(*values, *mask, options.fill_min_neighbours, into.values, into.mask);
    values = &into.values;
    mask = &into.mask;
  }

  if (options.square_pixels && needs_square_pixels(image.geometry)) {
    out.geometry = square_pixel_geometry(image.geometry);
    PreprocessedImage::Buffers& into = out.work[values == &out.work[0].values ? 1 : 0];
    resample_rows(*values, *mask, image.geometry, out.geometry, into.values, into.mask,
                  &out.repeats_row_above);
    values = &into.values;
    mask = &into.mask;
  } else {
    out.geometry = image.geometry;
    out.repeats_row_above.assign(static_cast<std::size_t>(image.intensity.rows), 0);
  }
  const cv::Mat& filled = *values;
  const cv::Mat& filled_mask = *mask;

  // A header onto the last pass's mask, not a copy: nothing writes that buffer again before the
  // next frame, which rewrites `out` whole anyway (a copy cost 0.02 ms on a Mid-40 image).
  out.valid = filled_mask;
  out.intensity_scale = robust_max(*source, image.mask);
  to_gray(filled, filled_mask, out.repeats_row_above, out.intensity_scale, options.unobserved_value,
          out.gray);

  out.threshold = options.threshold ? *options.threshold
                                    : otsu_threshold(out.gray, filled_mask, out.repeats_row_above,
                                                     out.intensity_scale);
  if (!options.binarize) {
    out.gray.copyTo(out.detect);
  } else if (options.local_threshold) {
    const cv::Mat above =
        above_local_mean(filled, filled_mask, out.threshold, out.intensity_scale, options);
    out.detect.create(filled.size(), CV_8U);
    out.detect.setTo(0);
    out.detect.setTo(255, above & filled_mask);
    out.detect.setTo(options.unobserved_value, filled_mask == 0);
  } else {
    binarize(filled, filled_mask, out.repeats_row_above, out.threshold, options.unobserved_value,
             out.detect);
    // Holes take the class of their surroundings: a constant for all holes drew the gaps between
    // a sparse rosette's petals (a 10-frame Mid-40 image is 80 % unobserved away from its centre)
    // as thousands of black streaks on a white wall: no marker, but 3-5 times AprilTag's
    // clustering time, and a 17 cm tag at 2 m with gaps inside it was not found before 10 frames
    // (now from 2; docs/pipeline.md). The surroundings' class keeps a dark floor dark, where
    // all-white holes made random patterns that weak families (tag16h5, tag25h9) decoded.
    if (options.hole_class_block > 0)
      detail::classify_holes(filled_mask, options.hole_class_block, out.detect, out.hole_classes);
  }
  if (options.blur_sigma > 0) {
    cv::GaussianBlur(out.detect, out.detect, cv::Size(0, 0), options.blur_sigma);
  }
}

DetectorImages detector_images(const PreprocessedImage& image, const PreprocessOptions& options) {
  DetectorImages images{image.detect, cv::Mat(), cv::Mat()};
  if (options.binarize) {
    images.gray = image.gray;
    images.valid = image.valid;
  }
  return images;
}

}  // namespace iilfm
