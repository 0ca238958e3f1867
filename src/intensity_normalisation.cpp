#include "iilfm/intensity_normalisation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "cpu_clones.hpp"
#include "iilfm/projection.hpp"
#include "parallel_parts.hpp"

namespace iilfm {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

// Mean range of the observed pixels of the window around (row, col), their centroid (column,
// row), and whether the window holds any. The sums are turned into means once per pixel in a
// loop that vectorises (`to_means`), so the five windows read per pixel cost loads, not 15
// scalar divisions.
struct WindowMean {
  const cv::Mat& range;
  const cv::Mat& count;
  const cv::Mat& col;
  const cv::Mat& row;
  struct Value {
    float range = 0, col = 0, row = 0;
    bool valid = false;
  };
  Value at(int r, int c) const {
    Value v;
    v.valid = count.at<float>(r, c) > 0.5f;
    if (!v.valid) return v;
    v.range = range.at<float>(r, c);
    v.col = col.at<float>(r, c);
    v.row = row.at<float>(r, c);
    return v;
  }
};

// Window sums to window means, in place, where the window holds an observed pixel: rows
// [first, end).
IILFM_AVX2_CLONES void to_means(const cv::Mat& count, cv::Mat& range, cv::Mat& col, cv::Mat& row,
                                int first, int end) {
  const int cols = count.cols;
  for (int r = first; r < end; ++r) {
    const float* __restrict n = count.ptr<float>(r);
    float* __restrict rs = range.ptr<float>(r);
    float* __restrict cs = col.ptr<float>(r);
    float* __restrict ws = row.ptr<float>(r);
    for (int c = 0; c < cols; ++c) {
      const float divisor = n[c] > 0.5f ? n[c] : 1.0f;
      rs[c] /= divisor;
      cs[c] /= divisor;
      ws[c] /= divisor;
    }
  }
}

// One row of the window means and the rows a half-window above and below it.
struct InnerRows {
  const float *count, *range, *col, *row;
  const float *count_up, *range_up, *row_up;
  const float *count_down, *range_down, *row_down;
};

// The mean range and the centroid (column or row) of the windows before, about and after a pixel
// along one image axis.
struct AxisWindows {
  float before_range, before_at, centre_range, centre_at, after_range, after_at;
};

// Whether the two one-sided slopes along an axis (the windows before and about the pixel, about
// and after it) describe different surfaces: the windows then straddle a crease (a wall meeting the
// floor) or a depth edge, and the two-sided slope mixes them. `per_unit` turns range per pixel
// into the tangent of the incidence along the axis. A side shorter than half a pixel (missing,
// replaced by the pixel's own window) agrees with any. Within one plane the two tangents differ by
// noise and by their change over a window's width (about 0.1 at 60 deg of incidence, 0.5 at the
// 78 deg clamp), well inside the tolerance (1.4 and 2.9 there).
inline bool sides_disagree(const AxisWindows& w, float per_unit) {
  const float d_before = w.centre_at - w.before_at, d_after = w.after_at - w.centre_at;
  const bool both = (d_before > 0.5f) & (d_after > 0.5f);
  // The tangents rise_before / d_before and rise_after / d_after compared with both sides of the
  // test multiplied by d_before * d_after (positive where it counts): no division.
  const float rise_before = (w.centre_range - w.before_range) * per_unit;
  const float rise_after = (w.after_range - w.centre_range) * per_unit;
  const float difference = std::abs(rise_after * d_before - rise_before * d_after);
  const float steeper = std::max(std::abs(rise_before) * d_after, std::abs(rise_after) * d_before);
  return both & (difference > 0.5f * (d_before * d_after + steeper));
}

// cos(incidence) from the range differences across (over d_col columns) and down (over d_row
// rows) of the windows about a pixel. Where the windows do not see one surface, no correction:
// a slope steeper than the clamp allows (a board in front of a far wall) or one-sided slopes that
// disagree (sides_disagree: a crease, or an edge the windows straddle less steeply). Corrected
// there, the edge or the crease would glow: a wall's rows just above the floor came out 4-5
// times too bright on an OS1-128 at 18 m and took Otsu's threshold with them. Branch-free, so the
// loop calling it vectorises; a slope over a side too short is computed and discarded.
inline float cos_incidence_of(const AxisWindows& across, const AxisWindows& down, float per_az,
                              float per_el, float max_gain_sq) {
  const float per_range = 1.0f / across.centre_range;
  const float d_col = across.after_at - across.before_at, d_row = down.after_at - down.before_at;
  const float slope_az = (across.after_range - across.before_range) / d_col * per_az * per_range;
  const float slope_el = (down.before_range - down.after_range) / d_row * per_el * per_range;
  const float g_az = d_col > 0.5f ? slope_az : 0.0f, g_el = d_row > 0.5f ? slope_el : 0.0f;
  const float gain_sq = 1.0f + g_az * g_az + g_el * g_el;
  const float cosine = 1.0f / std::sqrt(gain_sq);
  const bool one_surface = (gain_sq <= max_gain_sq) & !sides_disagree(across, per_az * per_range) &
                           !sides_disagree(down, per_el * per_range);
  return one_surface ? cosine : 1.0f;
}

// estimate_cos_incidence's arithmetic for the columns whose side windows lie in the image: every
// value loaded before the selects for the missing windows (a conditional load keeps GCC from
// vectorising).
IILFM_AVX2_CLONES void cos_incidence_inside(const InnerRows& in,
                                            const std::uint8_t* __restrict mask, int a, int begin,
                                            int end, float per_az, float per_el, float max_gain_sq,
                                            float* __restrict out) {
  const float* __restrict n0 = in.count;
  const float* __restrict range0 = in.range;
  const float* __restrict col0 = in.col;
  const float* __restrict row0 = in.row;
  const float* __restrict n_up = in.count_up;
  const float* __restrict range_up = in.range_up;
  const float* __restrict row_up = in.row_up;
  const float* __restrict n_down = in.count_down;
  const float* __restrict range_down = in.range_down;
  const float* __restrict row_down = in.row_down;
  for (int c = begin; c < end; ++c) {
    const float centre_range = range0[c], centre_col = col0[c], centre_row = row0[c];
    const bool left_ok = n0[c - a] > 0.5f, right_ok = n0[c + a] > 0.5f;
    const bool above_ok = n_up[c] > 0.5f, below_ok = n_down[c] > 0.5f;
    const float lr = range0[c - a], lc = col0[c - a], rr = range0[c + a], rc = col0[c + a];
    const float ar = range_up[c], aw = row_up[c], br = range_down[c], bw = row_down[c];
    const float left_range = left_ok ? lr : centre_range, left_col = left_ok ? lc : centre_col;
    const float right_range = right_ok ? rr : centre_range;
    const float right_col = right_ok ? rc : centre_col;
    const float above_range = above_ok ? ar : centre_range, above_row = above_ok ? aw : centre_row;
    const float below_range = below_ok ? br : centre_range, below_row = below_ok ? bw : centre_row;
    const float cosine =
        cos_incidence_of({left_range, left_col, centre_range, centre_col, right_range, right_col},
                         {above_range, above_row, centre_range, centre_row, below_range, below_row},
                         per_az, per_el, max_gain_sq);
    const bool known = (mask[c] != 0) & (n0[c] > 0.5f) & (centre_range > 0);
    out[c] = known ? cosine : 1.0f;
  }
}

// out[c] = terms[0][c] + terms[1][c] + ... (added in that order) for c < cols, 32 columns at a
// time in registers. Adding row by row into `out` stalled on 4K aliasing: a 2048-column image's
// rows lie 8 KB apart, so each load looked to the CPU as if it waited for the store before it.
// Eight floats: one AVX register, or two SSE ones. Unaligned and allowed to alias floats, so
// a row's floats can be read and written through it.
using Floats8 = float __attribute__((vector_size(32), aligned(4), may_alias));

IILFM_AVX2_CLONES void add_terms(const float* const* terms, int count, int cols,
                                 float* __restrict out) {
  int c = 0;
  for (; c + 32 <= cols; c += 32) {
    const auto* first = reinterpret_cast<const Floats8*>(terms[0] + c);
    Floats8 a0 = first[0], a1 = first[1], a2 = first[2], a3 = first[3];
    for (int k = 1; k < count; ++k) {
      const auto* term = reinterpret_cast<const Floats8*>(terms[k] + c);
      a0 += term[0];
      a1 += term[1];
      a2 += term[2];
      a3 += term[3];
    }
    auto* to = reinterpret_cast<Floats8*>(out + c);
    to[0] = a0;
    to[1] = a1;
    to[2] = a2;
    to[3] = a3;
  }
  for (; c < cols; ++c) {
    float acc = terms[0][c];
    for (int k = 1; k < count; ++k) acc += terms[k][c];
    out[c] = acc;
  }
}

// Window sums of `in` (CV_32F) over the (2a+1) x (2b+1) window about every pixel, zero outside the
// image. Small windows (the Ouster presets': 7 x 7 at 1024 columns) are summed directly, across
// then down, each sum's terms in a fixed order (four cv::boxFilter calls took 1.65 ms on the
// OS1-128 bench image; the direct sums took `Preprocess/os1-128` from 2.4-2.9 to 1.9 ms); larger
// ones go to cv::boxFilter, whose running sums cost the same at any size.
constexpr int kDirectMax = 8;

// One row's sums along it over 2a + 1 columns into `across`, from `padded`: the row with a zeros
// either side.
void sum_across(const std::vector<float>& padded, int a, int cols, float* across) {
  const float* terms[2 * kDirectMax + 1];
  for (int k = 0; k <= 2 * a; ++k) terms[k] = padded.data() + k;
  add_terms(terms, 2 * a + 1, cols, across);
}

// A row's observed-pixel weights (1 or 0) and the weights times their column numbers.
IILFM_AVX2_CLONES void weights_of_row(const std::uint8_t* __restrict mask, int cols,
                                      float* __restrict weight, float* __restrict col) {
  for (int c = 0; c < cols; ++c) {
    weight[c] = mask[c] ? 1.0f : 0.0f;  // masks hold 0 or 255
    col[c] = weight[c] * static_cast<float>(c);
  }
}

// Rows [first, end) of the sums of `across` down 2b + 1 rows, into `sum`.
void sums_down(const cv::Mat& across, int b, int first, int end, cv::Mat& sum) {
  const float* terms[2 * kDirectMax + 1];
  for (int r = first; r < end; ++r) {
    const int top = std::max(0, r - b), bottom = std::min(across.rows - 1, r + b);
    for (int rr = top; rr <= bottom; ++rr) terms[rr - top] = across.ptr<float>(rr);
    add_terms(terms, bottom - top + 1, across.cols, sum.ptr<float>(r));
  }
}

// sum[c] = before[c] + scale_in * entering[c] - scale_out * leaving[c].
IILFM_AVX2_CLONES void slide_row(const float* before, const float* __restrict entering,
                                 float scale_in, const float* __restrict leaving, float scale_out,
                                 int cols, float* sum) {
  for (int c = 0; c < cols; ++c)
    sum[c] = before[c] + scale_in * entering[c] - scale_out * leaving[c];
}

// Rows [first, end) of the sums down 2b + 1 rows of `across`, each row r' weighted by r' when
// `by_row` (so the weight's sums along rows give those of the weighted row numbers): the first
// row summed whole, each next one from the one above, a row entering and one leaving. Only for
// integers (every partial sum an integer below 2^24), where that is exact: the same floats as
// sums_down, in two additions a pixel instead of 2b.
void sliding_sums_down(const cv::Mat& across, int b, int first, int end, bool by_row,
                       cv::Mat& sum) {
  if (first >= end) return;
  const int rows = across.rows, cols = across.cols;
  thread_local std::vector<float> zeros;
  zeros.assign(static_cast<std::size_t>(cols), 0.0f);
  const auto row_of = [&](int r) {
    return r >= 0 && r < rows ? across.ptr<float>(r) : zeros.data();
  };
  const auto weight_of = [&](int r) { return by_row ? static_cast<float>(r) : 1.0f; };
  float* top_sum = sum.ptr<float>(first);
  std::fill(top_sum, top_sum + cols, 0.0f);
  for (int r = std::max(0, first - b); r <= std::min(rows - 1, first + b); ++r)
    slide_row(top_sum, row_of(r), weight_of(r), zeros.data(), 0.0f, cols, top_sum);
  for (int r = first + 1; r < end; ++r)
    slide_row(sum.ptr<float>(r - 1), row_of(r + b), weight_of(r + b), row_of(r - b - 1),
              weight_of(r - b - 1), cols, sum.ptr<float>(r));
}

// Threads take at least this many pixels each (detail::parts_for).
constexpr std::size_t kMinPixelsPerPart = 65536;

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
                            NormalisationBuffers& work, cv::Mat& cos_incidence, int threads) {
  const ImageGeometry& g = image.geometry;
  const int rows = image.range.rows, cols = image.range.cols;
  cos_incidence.create(rows, cols, CV_32F);
  if (rows == 0 || cols == 0 || !(g.res_h > 0) || !(g.res_v > 0)) {
    cos_incidence.setTo(1.0f);
    return;
  }
  const double half = options.normal_half_window_deg * kDegToRad;
  const int a = std::max(1, static_cast<int>(std::lround(half / g.res_h)));
  const int b = std::max(1, static_cast<int>(std::lround(half / g.res_v)));
  const bool direct = a <= kDirectMax && b <= kDirectMax;
  const int parts = detail::parts_for(threads, image.range.total(), kMinPixelsPerPart);
  // The range image is 0 where unobserved, so its window sum is the observed pixels' sum. Column
  // and row sums are sums of integers below 2^24: exact in float.
  const cv::Mat* inputs[4] = {&image.range, &work.weight, &work.weighted_col, &work.weighted_row};
  cv::Mat* sums[4] = {&work.range_sum, &work.weight_sum, &work.col_sum, &work.row_sum};
  for (cv::Mat* m : {&work.range_sum, &work.weight_sum, &work.col_sum, &work.row_sum})
    m->create(rows, cols, CV_32F);
  if (direct) {  // the sums along rows of the range, weight and column; cv::boxFilter keeps its own
    for (int k = 0; k < 3; ++k) work.across[k].create(rows, cols, CV_32F);
  } else {  // whole images of the weights for cv::boxFilter
    for (cv::Mat* m : {&work.weight, &work.weighted_col, &work.weighted_row})
      m->create(rows, cols, CV_32F);
  }
  // Three passes over the rows, each after the whole of the one before: a window reaches b rows
  // into the neighbouring parts. Weights and the sums along rows, then down, then the cosines.
  detail::in_row_parts(rows, parts, [&](int first, int end) {
    if (!direct) {
      for (int r = first; r < end; ++r) {
        const std::uint8_t* m = image.mask.ptr<std::uint8_t>(r);
        float* w = work.weight.ptr<float>(r);
        weights_of_row(m, cols, w, work.weighted_col.ptr<float>(r));
        float* __restrict wr = work.weighted_row.ptr<float>(r);
        for (int c = 0; c < cols; ++c) wr[c] = w[c] * static_cast<float>(r);
      }
      return;
    }
    // Each row's range, weights and column numbers go straight into rows padded with zeros (no
    // whole images of the weights), and are summed along the row from there. The row numbers'
    // sums are the weight's times the row (sliding_sums_down).
    thread_local std::vector<float> range_row, weight_row, col_row;
    for (std::vector<float>* row : {&range_row, &weight_row, &col_row})
      row->assign(static_cast<std::size_t>(cols + 2 * a), 0.0f);
    for (int r = first; r < end; ++r) {
      const float* range = image.range.ptr<float>(r);
      std::copy(range, range + cols, range_row.data() + a);
      weights_of_row(image.mask.ptr<std::uint8_t>(r), cols, weight_row.data() + a,
                     col_row.data() + a);
      sum_across(range_row, a, cols, work.across[0].ptr<float>(r));
      sum_across(weight_row, a, cols, work.across[1].ptr<float>(r));
      sum_across(col_row, a, cols, work.across[2].ptr<float>(r));
    }
  });
  if (!direct)
    for (int k = 0; k < 4; ++k)
      cv::boxFilter(*inputs[k], *sums[k], CV_32F, cv::Size(2 * a + 1, 2 * b + 1), cv::Point(-1, -1),
                    false, cv::BORDER_CONSTANT);
  detail::in_row_parts(rows, parts, [&](int first, int end) {
    if (direct) {
      // Along a row the row number is constant: its sums are the weight's times the row.
      sums_down(work.across[0], b, first, end, work.range_sum);
      sliding_sums_down(work.across[1], b, first, end, false, work.weight_sum);
      sliding_sums_down(work.across[2], b, first, end, false, work.col_sum);
      sliding_sums_down(work.across[1], b, first, end, true, work.row_sum);
    }
    to_means(work.weight_sum, work.range_sum, work.col_sum, work.row_sum, first, end);
  });
  const WindowMean mean{work.range_sum, work.weight_sum, work.col_sum, work.row_sum};
  const float max_gain_sq =
      static_cast<float>(1.0 / (options.min_cos_incidence * options.min_cos_incidence));

  detail::in_row_parts(rows, parts, [&](int first, int end) {
    for (int r = first; r < end; ++r) {
      const int up = std::max(0, r - b), down = std::min(rows - 1, r + b);
      const double el = g.elevation_of_v(r);
      // Elevation per row about this row (ring rows are not evenly spaced).
      const double per_row =
          down > up ? std::abs(g.elevation_of_v(up) - g.elevation_of_v(down)) / (down - up)
                    : g.res_v;
      const float per_az = static_cast<float>(1.0 / (g.res_h * std::max(0.05, std::cos(el))));
      const float per_el = static_cast<float>(1.0 / per_row);
      const std::uint8_t* m = image.mask.ptr<std::uint8_t>(r);
      float* out = cos_incidence.ptr<float>(r);
      std::fill(out, out + cols, 1.0f);
      // Near the left and right borders a side window is clamped to the image: per pixel.
      const auto at_border = [&](int c) {
        if (!m[c]) return;
        const WindowMean::Value centre = mean.at(r, c);
        if (!centre.valid || !(centre.range > 0)) return;
        WindowMean::Value left = mean.at(r, std::max(0, c - a));
        WindowMean::Value right = mean.at(r, std::min(cols - 1, c + a));
        WindowMean::Value above = mean.at(up, c), below = mean.at(down, c);
        if (!left.valid) left = centre;
        if (!right.valid) right = centre;
        if (!above.valid) above = centre;
        if (!below.valid) below = centre;
        out[c] = cos_incidence_of(
            {left.range, left.col, centre.range, centre.col, right.range, right.col},
            {above.range, above.row, centre.range, centre.row, below.range, below.row}, per_az,
            per_el, max_gain_sq);
      };
      const int inner_begin = std::min(a, cols), inner_end = std::max(inner_begin, cols - a);
      for (int c = 0; c < inner_begin; ++c) at_border(c);
      for (int c = inner_end; c < cols; ++c) at_border(c);
      // Inside, the same arithmetic with every value loaded and selects for the missing windows,
      // so the loop vectorises (with branches and divisions it took 14 ns a pixel on the
      // OS1-128).
      const InnerRows rows_of{work.weight_sum.ptr<float>(r),   work.range_sum.ptr<float>(r),
                              work.col_sum.ptr<float>(r),      work.row_sum.ptr<float>(r),
                              work.weight_sum.ptr<float>(up),  work.range_sum.ptr<float>(up),
                              work.row_sum.ptr<float>(up),     work.weight_sum.ptr<float>(down),
                              work.range_sum.ptr<float>(down), work.row_sum.ptr<float>(down)};
      cos_incidence_inside(rows_of, m, a, inner_begin, inner_end, per_az, per_el, max_gain_sq, out);
    }
  });
}

void normalise_intensity(const ProjectedImage& image, const NormalisationOptions& options,
                         NormalisationBuffers& work, cv::Mat& out, int threads) {
  if (options.mode == IntensityNormalisation::kNone) return;
  const int rows = image.intensity.rows, cols = image.intensity.cols;
  out.create(rows, cols, CV_32F);
  const bool incidence = options.mode == IntensityNormalisation::kRangeIncidence;
  if (incidence) estimate_cos_incidence(image, options, work, work.cos_incidence, threads);
  const float per_ref_sq = static_cast<float>(1.0 / (options.reference_m * options.reference_m));
  const int parts = detail::parts_for(threads, image.intensity.total(), kMinPixelsPerPart);
  detail::in_row_parts(rows, parts, [&](int first, int end) {
    // Range: a pass that vectorises (the range is 0 where unobserved, so is the product).
    for (int r = first; r < end; ++r) {
      const float* __restrict i = image.intensity.ptr<float>(r);
      const float* __restrict d = image.range.ptr<float>(r);
      float* __restrict o = out.ptr<float>(r);
      for (int c = 0; c < cols; ++c) o[c] = i[c] * (d[c] * d[c] * per_ref_sq);
    }
    if (!incidence) return;
    cv::Mat part = out.rowRange(first, end);
    cv::divide(part, work.cos_incidence.rowRange(first, end), part);
  });
}

}  // namespace iilfm
