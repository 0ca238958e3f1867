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
#include "parallel_parts.hpp"

namespace iilfm {

namespace {

// Mean of the observed 8-neighbours for unobserved pixels with at least `min_neighbours` of them.
// Only the detector sees these values: no 3-D point is ever made from a filled pixel. One pass
// over the rows: each row's observed values and observed count once (kept for the next two rows),
// their 3-row column sums, then 3-column sums of those. The loops vectorise (checked with
// -fopt-info-vec); the per-pixel one selects rather than blends, since 0 x an infinite mean would
// be NaN.
//
// With `skip_uniform_blocks`, rows go in blocks of 32 pixels, flagged as each row is loaded (any
// pixel observed, every one 255): a block observed throughout keeps its values, one with nothing
// observed in it, its neighbour blocks and the rows above and below gets nothing (what the sums
// give: no count reaches `needed`), and only runs of the others are summed. The same floats.
// Measured, both passes alone: ring images 40 % faster (ULTRA Puck 0.072 -> 0.041 ms, OS1-128
// 0.34 -> 0.19; 90 % of their blocks skipped), but 1- and 10-frame Mid-40 images 10-15 % slower
// (few blocks to skip, and the flags cost about 1/8 of a row's sums).
//
// Writes rows [first_row, end_row) of `filled` and `filled_mask`, which the caller has sized like
// `intensity`: parts of the rows may go to different threads.
IILFM_AVX2_CLONES void fill_holes(const cv::Mat& intensity, const cv::Mat& mask, int min_neighbours,
                                  bool skip_uniform_blocks, int first_row, int end_row,
                                  cv::Mat& filled, cv::Mat& filled_mask) {
  const int rows = intensity.rows, cols = intensity.cols;
  constexpr int kBlock = 32;
  constexpr std::uint8_t kAny = 1, kEvery = 2;                 // a block's flags
  constexpr std::uint8_t kSum = 0, kObserved = 1, kEmpty = 2;  // what to do with it
  constexpr int kMinSkippedRun = 4;  // shorter runs are summed: their set-up costs more
  const int blocks = skip_uniform_blocks ? (cols + kBlock - 1) / kBlock : 1;
  // Rows padded by one zero column on each side: three rows' observed values and counts (row r in
  // slot r % 3) and a fourth of zeros for the rows beyond the image; the same for the block flags,
  // padded by an empty block each side.
  const std::size_t padded = static_cast<std::size_t>(cols) + 2;
  const std::size_t flag_row = static_cast<std::size_t>(blocks) + 2;
  thread_local std::vector<float> row_values, row_counts, value_sum, count_sum;
  thread_local std::vector<std::uint8_t> row_flags, block_kinds, flags_around;
  row_values.assign(4 * padded, 0.0f);
  row_counts.assign(4 * padded, 0.0f);
  row_flags.assign(4 * flag_row, 0);
  value_sum.resize(padded);
  count_sum.resize(padded);
  block_kinds.assign(static_cast<std::size_t>(blocks), kSum);
  flags_around.resize(flag_row);
  std::uint8_t* const kinds = block_kinds.data();
  const auto load_row = [&](int r) {
    const std::size_t slot = static_cast<std::size_t>(r % 3);
    float* __restrict vs = row_values.data() + slot * padded + 1;
    float* __restrict cs = row_counts.data() + slot * padded + 1;
    const float* __restrict v = intensity.ptr<float>(r);
    const std::uint8_t* __restrict m = mask.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      const float observed = m[c] ? 1.0f : 0.0f;
      vs[c] = v[c] * observed;
      cs[c] = observed;
    }
    if (!skip_uniform_blocks) return;
    std::uint8_t* __restrict flags = row_flags.data() + slot * flag_row + 1;
    const int whole = cols / kBlock;
    for (int b = 0; b < whole; ++b) {  // eight mask bytes a word, four words a block
      std::uint64_t word[4];
      std::memcpy(word, m + b * kBlock, sizeof word);
      const std::uint64_t any = word[0] | word[1] | word[2] | word[3];
      const std::uint64_t every = word[0] & word[1] & word[2] & word[3];
      flags[b] = static_cast<std::uint8_t>((any ? kAny : 0) | (every == ~0ull ? kEvery : 0));
    }
    if (whole < blocks) {  // the last, partial block
      std::uint8_t any = 0, every = 0xFF;
      for (int c = whole * kBlock; c < cols; ++c) {
        any |= m[c];
        every &= m[c];
      }
      flags[whole] = static_cast<std::uint8_t>((any ? kAny : 0) | (every == 0xFF ? kEvery : 0));
    }
  };
  // Row r's slot (r % 3), or the zero row beyond the image.
  const auto slot_of = [&](int r) -> std::size_t {
    return r < 0 || r >= rows ? 3 : static_cast<std::size_t>(r % 3);
  };
  // The kind of each block of the row between slots s0 and s2 (byte loops, so they vectorise).
  const float needed = static_cast<float>(min_neighbours) - 0.5f;
  const auto choose_kinds = [&](std::size_t s0, std::size_t s1, std::size_t s2) {
    const std::uint8_t* __restrict f0 = row_flags.data() + s0 * flag_row;
    const std::uint8_t* __restrict f1 = row_flags.data() + s1 * flag_row;
    const std::uint8_t* __restrict f2 = row_flags.data() + s2 * flag_row;
    std::uint8_t* __restrict column = flags_around.data();
    for (std::size_t b = 0; b < flag_row; ++b) column[b] = f0[b] | f1[b] | f2[b];
    const std::uint8_t empty = needed > 0 ? kEmpty : kSum;
    for (int b = 0; b < blocks; ++b) {
      const int near = column[b] | column[b + 1] | column[b + 2];
      const std::uint8_t none_near = (near & kAny) ? kSum : empty;
      kinds[b] = (f1[b + 1] & kEvery) ? kObserved : none_near;
    }
    for (int b = 0; b < blocks;) {
      int end = b + 1;
      while (end < blocks && kinds[end] == kinds[b]) ++end;
      if (end - b < kMinSkippedRun && kinds[b] != kSum)
        std::memset(kinds + b, kSum, static_cast<std::size_t>(end - b));
      b = end;
    }
  };
  if (first_row > 0) load_row(first_row - 1);
  if (first_row < end_row) load_row(first_row);
  for (int r = first_row; r < end_row; ++r) {
    if (r + 1 < rows) load_row(r + 1);  // into the slot of row r - 2, no longer needed
    const std::size_t s0 = slot_of(r - 1) * padded, s1 = slot_of(r) * padded,
                      s2 = slot_of(r + 1) * padded;
    if (skip_uniform_blocks) choose_kinds(slot_of(r - 1), slot_of(r), slot_of(r + 1));
    const float* __restrict v = intensity.ptr<float>(r);
    const std::uint8_t* __restrict m = mask.ptr<std::uint8_t>(r);
    float* __restrict out = filled.ptr<float>(r);
    std::uint8_t* __restrict out_mask = filled_mask.ptr<std::uint8_t>(r);
    for (int b = 0; b < blocks;) {  // runs of blocks of one kind (one run: the whole row)
      const std::uint8_t kind = kinds[b];
      int end = b + 1;
      while (end < blocks && kinds[end] == kind) ++end;
      const int c0 = b * kBlock, c1 = end == blocks ? cols : end * kBlock;
      const auto n = static_cast<std::size_t>(c1 - c0);
      b = end;
      if (kind == kObserved) {
        std::memcpy(out + c0, v + c0, sizeof(float) * n);
        std::memset(out_mask + c0, 255, n);
        continue;
      }
      if (kind == kEmpty) {
        std::memset(out + c0, 0, sizeof(float) * n);
        std::memset(out_mask + c0, 0, n);
        continue;
      }
      // Each column's 3-row sums, added top to bottom as a running sum from zero would (the same
      // floats), over the run's columns and one each side (sum k is of image column k - 1). Two
      // loops: GCC vectorises neither when one holds both sums.
      float* __restrict vs = value_sum.data();
      float* __restrict cs = count_sum.data();
      {
        const float* __restrict x = row_values.data() + s0;
        const float* __restrict y = row_values.data() + s1;
        const float* __restrict z = row_values.data() + s2;
        for (int k = c0; k < c1 + 2; ++k) vs[k] = x[k] + y[k] + z[k];
      }
      {
        const float* __restrict x = row_counts.data() + s0;
        const float* __restrict y = row_counts.data() + s1;
        const float* __restrict z = row_counts.data() + s2;
        for (int k = c0; k < c1 + 2; ++k) cs[k] = x[k] + y[k] + z[k];
      }
      // Every value is loaded before the selects, so the loop has no conditional load and
      // vectorises (masks hold 0 or 255).
      for (int c = c0; c < c1; ++c) {
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
}

// Gray 255 is this many times the 99th percentile of observed intensity. A marker is a small
// part of most images and its white paper is among the brightest surfaces in them: at the
// percentile itself the paper was clipped to 255 wherever walls filled the other 99 %, which
// biased the white reference of AprilTag's gray decoding (docs/detectors.md) and lost far markers
// (docs/sensors.md, "Detection range": the Avia's 40 cm tag went from 10 to 18 m with 2).
constexpr double kGrayHeadroom = 2.0;

// The largest intensity of the observed pixels (0 when there is none).
double max_observed(const cv::Mat& intensity, const cv::Mat& mask) {
  double largest = 0;
  cv::minMaxLoc(intensity, nullptr, &largest, nullptr, nullptr, mask);
  return cv::countNonZero(mask) > 0 ? largest : 0;
}

// The 99th percentile of observed values, so a few retro-reflectors do not darken everything
// else. A grid of at most about 16k pixels (every 4th pixel of every 2nd row, sparser on large
// images) is plenty for a percentile of a display scale (its rank within 0.2 % at two standard
// errors) and keeps the selection off the frame's critical path: 74k values of a Mid-40 image took
// 0.4 ms.
constexpr double kLeastPercentile = 1e-6;  // percentile_99's floor: a scale never 0

double percentile_99(const cv::Mat& intensity, const cv::Mat& mask) {
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
  return std::max(kLeastPercentile, static_cast<double>(values[k]));
}

// Otsu's threshold over the observed gray values, returned in intensity units. A row that
// repeats the one above (`repeats_row_above`) is counted with it: its row's count goes up by one.
double otsu_threshold(const cv::Mat& gray, const cv::Mat& mask,
                      const std::vector<std::uint8_t>& repeats_row_above, double scale) {
  // Eight mask bytes at a time: runs of unobserved pixels (outside a Livox's circle, a sparse
  // frame's gaps) are skipped whole, and the rest go without a branch on the mask, unobserved
  // ones to bins 256-511. Four histograms, so that neighbouring pixels of one value do not wait
  // on each other's increments.
  int counts[4][512] = {};
  const auto bin = [](std::uint8_t value, std::uint8_t observed) {
    return value | (static_cast<int>(observed == 0) << 8);
  };
  for (int r = 0; r < gray.rows;) {
    int copies = 1;
    while (r + copies < gray.rows && repeats_row_above[static_cast<std::size_t>(r + copies)])
      ++copies;
    const std::uint8_t* g = gray.ptr<std::uint8_t>(r);
    const std::uint8_t* m = mask.ptr<std::uint8_t>(r);
    int c = 0;
    for (; c + 8 <= gray.cols; c += 8) {
      std::uint64_t word;
      std::memcpy(&word, m + c, sizeof word);
      if (word == 0) continue;
      for (int k = 0; k < 8; k += 4) {
        counts[0][bin(g[c + k], m[c + k])] += copies;
        counts[1][bin(g[c + k + 1], m[c + k + 1])] += copies;
        counts[2][bin(g[c + k + 2], m[c + k + 2])] += copies;
        counts[3][bin(g[c + k + 3], m[c + k + 3])] += copies;
      }
    }
    for (; c < gray.cols; ++c) counts[0][bin(g[c], m[c])] += copies;
    r += copies;
  }
  int histogram[256] = {};
  int total = 0;
  for (int i = 0; i < 256; ++i) {
    histogram[i] = counts[0][i] + counts[1][i] + counts[2][i] + counts[3][i];
    total += histogram[i];
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

// The local threshold's window sums, kept across frames: a frame of one size allocates nothing
// (as OpenCV temporaries these were a dozen fresh image-sized buffers a frame, whose first touch
// cost 15 ms on a Mid-40 image, and cv::boxFilter allocates its own row buffers on every call).
struct LocalThresholdBuffers {
  cv::Mat weight, values, squares, sum, sum_sq, count;
  std::vector<double> down;   // one row of the sums down a window's rows
  std::vector<float> padded;  // the same in float, with a half window of zeros either side
};

// The default window's half width (PreprocessOptions::local_window 15).
constexpr int kLocalHalfWindow = 7;

// Sums along a row over 2 kHalf + 1 values of `padded` (a row with kHalf values either side of
// [0, cols)), each held in a register while its terms are added in order: the same floats as the
// generic loop below, in half its loads and stores.
template <int kHalf>
inline void sums_along(const float* __restrict padded, int cols, float* __restrict sum) {
  for (int c = 0; c < cols; ++c) {
    float acc = padded[c - kHalf];
    for (int k = 1 - kHalf; k <= kHalf; ++k) acc += padded[c + k];
    sum[c] = acc;
  }
}

// Sums of `in` (CV_32F) over the (2 half + 1)-square window about every pixel, zero outside the
// image, into `out`: running sums down the columns in double (added and dropped a row at a time,
// vectorised across the row), then direct sums along each row in float, every sum's terms in one
// fixed order.
IILFM_AVX2_CLONES void window_sums(const cv::Mat& in, int half, LocalThresholdBuffers& b,
                                   cv::Mat& out) {
  const int rows = in.rows, cols = in.cols;
  b.down.assign(static_cast<std::size_t>(cols), 0.0);
  b.padded.assign(static_cast<std::size_t>(cols + 2 * half), 0.0f);
  double* __restrict down = b.down.data();
  float* __restrict padded = b.padded.data() + half;
  const auto add_row = [&](int r, double sign) {
    if (r < 0 || r >= rows) return;
    const float* __restrict row = in.ptr<float>(r);
    for (int c = 0; c < cols; ++c) down[c] += sign * static_cast<double>(row[c]);
  };
  for (int r = 0; r < half; ++r) add_row(r, 1.0);
  for (int r = 0; r < rows; ++r) {
    add_row(r + half, 1.0);
    add_row(r - half - 1, -1.0);
    for (int c = 0; c < cols; ++c) padded[c] = static_cast<float>(down[c]);
    float* __restrict sum = out.ptr<float>(r);
    if (half == kLocalHalfWindow) {
      sums_along<kLocalHalfWindow>(padded, cols, sum);
    } else {
      for (int c = 0; c < cols; ++c) sum[c] = padded[c - half];
      for (int k = 1 - half; k <= half; ++k) {
        const float* __restrict shifted = padded + k;
        for (int c = 0; c < cols; ++c) sum[c] += shifted[c];
      }
    }
  }
}

// Each valid pixel's weight (1), value and square; unobserved pixels weigh nothing.
IILFM_AVX2_CLONES void weighted_values(const cv::Mat& filled, const cv::Mat& valid,
                                       LocalThresholdBuffers& b) {
  const int rows = filled.rows, cols = filled.cols;
  for (int r = 0; r < rows; ++r) {
    const float* __restrict f = filled.ptr<float>(r);
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(r);
    float* __restrict w = b.weight.ptr<float>(r);
    float* __restrict v = b.values.ptr<float>(r);
    float* __restrict q = b.squares.ptr<float>(r);
    for (int c = 0; c < cols; ++c) {
      w[c] = m[c] ? 1.0f : 0.0f;  // masks hold 0 or 255
      v[c] = f[c] * w[c];
      q[c] = v[c] * f[c];
    }
  }
}

// The binary image from the window sums: white where brighter than the valid pixels' mean around
// it, or, where the window is nearly flat (its spread at most `min_spread`), than the global
// threshold; unobserved pixels `unobserved`.
IILFM_AVX2_CLONES void above_local_means(const cv::Mat& filled, const cv::Mat& valid,
                                         const LocalThresholdBuffers& b, float global_threshold,
                                         float min_spread_sq, std::uint8_t unobserved,
                                         cv::Mat& detect) {
  const int rows = filled.rows, cols = filled.cols;  // locals: the byte stores could alias them
  for (int r = 0; r < rows; ++r) {
    const float* __restrict f = filled.ptr<float>(r);
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(r);
    const float* __restrict sum = b.sum.ptr<float>(r);
    const float* __restrict sum_sq = b.sum_sq.ptr<float>(r);
    const float* __restrict count = b.count.ptr<float>(r);
    std::uint8_t* __restrict out = detect.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      const float n = std::max(count[c], 1.0f);
      const float mean = sum[c] / n;
      const float variance = sum_sq[c] / n - mean * mean;
      const float level = variance > min_spread_sq ? mean : global_threshold;
      const std::uint8_t white = f[c] > level ? 255 : 0;
      out[c] = m[c] ? white : unobserved;
    }
  }
}

// `detect` white where brighter than the valid pixels' mean around it; where the window is
// nearly flat (a wall, the sky), where brighter than the global threshold.
void local_threshold(const cv::Mat& filled, const cv::Mat& valid, double global_threshold,
                     double percentile_99, const PreprocessOptions& options, cv::Mat& detect) {
  thread_local LocalThresholdBuffers b;
  const int w = std::max(3, options.local_window | 1);
  for (cv::Mat* m : {&b.weight, &b.values, &b.squares}) m->create(filled.size(), CV_32F);
  weighted_values(filled, valid, b);
  for (cv::Mat* m : {&b.sum, &b.sum_sq, &b.count}) m->create(filled.size(), CV_32F);
  window_sums(b.values, w / 2, b, b.sum);
  window_sums(b.squares, w / 2, b, b.sum_sq);
  window_sums(b.weight, w / 2, b, b.count);
  const double min_spread = options.local_min_contrast * percentile_99;
  detect.create(filled.size(), CV_8U);
  above_local_means(filled, valid, b, static_cast<float>(global_threshold),
                    static_cast<float>(min_spread * min_spread),
                    static_cast<std::uint8_t>(options.unobserved_value), detect);
}

// The row that row `r` of a resampled image repeats (itself when it does not repeat): the only
// rows whose values resample_rows writes.
int source_row(const std::vector<std::uint8_t>& repeats_row_above, int r) {
  while (r > 0 && repeats_row_above[static_cast<std::size_t>(r)]) --r;
  return r;
}

// 8-bit gray for display and for Otsu, rows [first_row, end_row) of `gray` (sized by the caller):
// intensity scaled so `scale` maps to 255; pixels still unobserved get `unobserved`. A row that
// repeats the one above is copied, except the first, which is computed from the row it repeats
// (the row above may be another thread's).
IILFM_AVX2_CLONES void to_gray(const cv::Mat& filled, const cv::Mat& valid,
                               const std::vector<std::uint8_t>& repeats_row_above, double scale,
                               int unobserved, int first_row, int end_row, cv::Mat& gray) {
  const float factor = static_cast<float>(255.0 / scale);
  const std::uint8_t hole = cv::saturate_cast<std::uint8_t>(unobserved);
  const int cols = filled.cols;  // a local: the byte stores below could alias the Mat's fields
  for (int r = first_row; r < end_row; ++r) {
    std::uint8_t* __restrict g = gray.ptr<std::uint8_t>(r);
    if (r > first_row && repeats_row_above[static_cast<std::size_t>(r)]) {
      std::memcpy(g, gray.ptr<std::uint8_t>(r - 1), static_cast<std::size_t>(cols));
      continue;
    }
    const int source = source_row(repeats_row_above, r);
    const float* __restrict v = filled.ptr<float>(source);
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(source);
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

// The naive global threshold, rows [first_row, end_row) of `detect` (sized by the caller): 255
// where brighter than `threshold`, 0 where not, `unobserved` where no value is known. A row that
// repeats the one above is copied, except the first (as in to_gray).
IILFM_AVX2_CLONES void binarize(const cv::Mat& filled, const cv::Mat& valid,
                                const std::vector<std::uint8_t>& repeats_row_above,
                                double threshold, int unobserved, int first_row, int end_row,
                                cv::Mat& detect) {
  const float t = static_cast<float>(threshold);
  const std::uint8_t hole = cv::saturate_cast<std::uint8_t>(unobserved);
  const int cols = filled.cols;
  for (int r = first_row; r < end_row; ++r) {
    std::uint8_t* __restrict d = detect.ptr<std::uint8_t>(r);
    if (r > first_row && repeats_row_above[static_cast<std::size_t>(r)]) {
      std::memcpy(d, detect.ptr<std::uint8_t>(r - 1), static_cast<std::size_t>(cols));
      continue;
    }
    const int source = source_row(repeats_row_above, r);
    const float* __restrict v = filled.ptr<float>(source);
    const std::uint8_t* __restrict m = valid.ptr<std::uint8_t>(source);
    for (int c = 0; c < cols; ++c) {
      const std::uint8_t level = v[c] > t ? 255 : 0;
      d[c] = static_cast<std::uint8_t>((level & m[c]) | (hole & ~m[c]));  // masks hold 0 or 255
    }
  }
}

// Threads take at least this many of the projected image's pixels each: a ring image's few
// thousand (its rows are copied out to square pixels) are done before a thread has started.
constexpr std::size_t kMinPixelsPerPart = 65536;

// The naive binary image's last steps. Holes take the class of their surroundings: a constant for
// all holes drew the gaps between a sparse rosette's petals (a 10-frame Mid-40 image is 80 %
// unobserved away from its centre) as thousands of black streaks on a white wall: no marker, but
// 3-5 times AprilTag's clustering time, and a 17 cm tag at 2 m with gaps inside it was not found
// before 10 frames (now from 2; docs/pipeline.md). The surroundings' class keeps a dark floor
// dark, where all-white holes made random patterns that weak families (tag16h5, tag25h9) decoded.
void classify_holes_and_blur(PreprocessedImage& image, const PreprocessOptions& options,
                             cv::Mat& detect) {
  if (options.hole_class_block > 0)
    detail::classify_holes(image.valid, options.hole_class_block, detect, image.hole_classes);
  if (options.blur_sigma > 0) cv::GaussianBlur(detect, detect, cv::Size(0, 0), options.blur_sigma);
}

}  // namespace

void preprocess(const ProjectedImage& image, const PreprocessOptions& options,
                PreprocessedImage& out) {
  const int parts = detail::parts_for(options.threads, image.intensity.total(), kMinPixelsPerPart);
  const cv::Mat* source = &image.intensity;
  if (options.normalise.mode != IntensityNormalisation::kNone) {
    normalise_intensity(image, options.normalise, out.normalise_work, out.normalised,
                        options.threads);
    source = &out.normalised;
  }
  // Hole filling alternates between two reused buffer pairs (a pass reads the previous one).
  const cv::Mat* values = source;
  const cv::Mat* mask = &image.mask;
  // Blocks on ring images, whose sky and full rings leave most blocks uniform (above), and after
  // the first pass on images of about a point per pixel (many Livox frames integrated), which it
  // leaves observed nearly throughout (86 % of the 60-frame Mid-40 image's blocks).
  const bool dense = static_cast<double>(image.points_projected) >=
                     0.5 * static_cast<double>(image.intensity.total());
  for (int pass = 0; options.fill_holes && pass < std::max(1, options.fill_passes); ++pass) {
    PreprocessedImage::Buffers& into = out.work[pass % 2];
    into.values.create(values->size(), CV_32F);
    into.mask.create(values->size(), CV_8U);
    const bool by_blocks = image.geometry.ring_rows() || (pass > 0 && dense);
    detail::in_row_parts(values->rows, parts, [&](int first_row, int end_row) {
      fill_holes(*values, *mask, options.fill_min_neighbours, by_blocks, first_row, end_row,
                 into.values, into.mask);
    });
    values = &into.values;
    mask = &into.mask;
  }

  if (options.square_pixels && needs_square_pixels(image.geometry)) {
    out.geometry = square_pixel_geometry(image.geometry);
    PreprocessedImage::Buffers& into = out.work[values == &out.work[0].values ? 1 : 0];
    // The rows that repeat the one above are read only by the local threshold's window sums:
    // otherwise their values are not copied (a megabyte for a VLP-16 image).
    resample_rows(*values, *mask, image.geometry, out.geometry, into.values, into.mask,
                  &out.repeats_row_above, options.local_threshold);
    values = &into.values;
    mask = &into.mask;
  } else {
    out.geometry = image.geometry;
    out.repeats_row_above.assign(static_cast<std::size_t>(image.intensity.rows), 0);
  }
  const cv::Mat& filled = *values;
  const cv::Mat& filled_mask = *mask;
  out.filled = filled;

  // A header onto the last pass's mask, not a copy: nothing writes that buffer again before the
  // next frame, which rewrites `out` whole anyway (a copy cost 0.02 ms on a Mid-40 image).
  out.valid = filled_mask;
  const double percentile = percentile_99(*source, image.mask);
  out.intensity_scale = kGrayHeadroom * percentile;
  out.gray.create(filled.size(), CV_8U);
  const auto gray_rows = [&](int first_row, int end_row) {
    to_gray(filled, filled_mask, out.repeats_row_above, out.intensity_scale,
            options.unobserved_value, first_row, end_row, out.gray);
  };
  const bool naive = options.binarize && !options.local_threshold;
  const auto binary_rows = [&](int first_row, int end_row) {
    binarize(filled, filled_mask, out.repeats_row_above, out.threshold, options.unobserved_value,
             first_row, end_row, out.detect);
  };
  if (naive) out.detect.create(filled.size(), CV_8U);
  // A fixed threshold above every observed intensity would leave the detectors a black image
  // (PreprocessOptions::replace_threshold_above_all), and a cloud whose intensity is 0 throughout
  // carries none to see markers in. The 99th percentile, already known, rules both out for nearly
  // every frame before the image is scanned for its largest value.
  std::optional<double> fixed = options.threshold;
  out.replaced_threshold.reset();
  out.threshold_above_all = false;
  out.no_intensity = false;
  out.max_intensity = 0;
  if ((fixed && percentile <= *fixed) || percentile <= kLeastPercentile) {
    out.max_intensity = max_observed(*source, image.mask);
    out.no_intensity = out.max_intensity <= 0;
    out.threshold_above_all = fixed && out.max_intensity <= *fixed;
    if (out.threshold_above_all && options.replace_threshold_above_all && !out.no_intensity) {
      out.replaced_threshold = *fixed;
      fixed.reset();
    }
  }
  if (fixed) {
    out.threshold = *fixed;
    // Both images in one pass over the rows when the threshold is known up front.
    detail::in_row_parts(filled.rows, parts, [&](int first_row, int end_row) {
      gray_rows(first_row, end_row);
      if (naive) binary_rows(first_row, end_row);
    });
  } else {
    detail::in_row_parts(filled.rows, parts, gray_rows);
    out.threshold =
        otsu_threshold(out.gray, filled_mask, out.repeats_row_above, out.intensity_scale);
    if (naive) detail::in_row_parts(filled.rows, parts, binary_rows);
  }
  if (!options.binarize) {
    out.gray.copyTo(out.detect);
  } else if (options.local_threshold) {
    local_threshold(filled, filled_mask, out.threshold, percentile, options, out.detect);
  }
  if (options.binarize) {
    classify_holes_and_blur(out, options, out.detect);
  } else if (options.blur_sigma > 0) {
    cv::GaussianBlur(out.detect, out.detect, cv::Size(0, 0), options.blur_sigma);
  }
}

double otsu_threshold(const PreprocessedImage& image) {
  return otsu_threshold(image.gray, image.valid, image.repeats_row_above, image.intensity_scale);
}

void binarize_at(PreprocessedImage& image, double threshold, const PreprocessOptions& options,
                 cv::Mat& detect) {
  detect.create(image.filled.size(), CV_8U);
  const int parts = detail::parts_for(options.threads, image.filled.total(), kMinPixelsPerPart);
  detail::in_row_parts(image.filled.rows, parts, [&](int first_row, int end_row) {
    binarize(image.filled, image.valid, image.repeats_row_above, threshold,
             options.unobserved_value, first_row, end_row, detect);
  });
  classify_holes_and_blur(image, options, detect);
}

void binarize_locally(PreprocessedImage& image, const PreprocessOptions& options, cv::Mat& detect) {
  local_threshold(image.filled, image.valid, image.threshold, image.intensity_scale / kGrayHeadroom,
                  options, detect);
  classify_holes_and_blur(image, options, detect);
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
