#include "ring_row_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace iilfm::detail {

namespace {

// Where the sample at `azimuth` lies right of column c's centre, in columns (as
// ring_pixels_of_points places it: one past a full circle's last column wraps to the first).
float offset_from_centre(float azimuth, int c, float u0, float inv_res_h, float u_end, float wrap) {
  float u = u0 - azimuth * inv_res_h;
  if (u >= u_end) u -= wrap;
  return u - static_cast<float>(c);
}

// Whether a spread sample of the row's single-point pixels lies on the grid: a row of a sweep on
// the grid is passed after a few dozen pixels.
bool sampled_on_grid(const float* azimuth, const std::int32_t* index, const std::int32_t* count,
                     int width, float u0, float inv_res_h, float u_end, float wrap) {
  constexpr int kProbes = 32;
  const int step = std::max(1, width / kProbes);
  for (int c = 0; c < width; c += step) {
    if (count[c] != 1) continue;
    const float d = offset_from_centre(azimuth[index[c]], c, u0, inv_res_h, u_end, wrap);
    if (std::abs(d) > kColumnOffsetTolerance) return false;
  }
  return true;
}

}  // namespace

void measure_column_offsets(const float* azimuth, ProjectedImage& image) {
  const ImageGeometry& g = image.geometry;
  const int width = g.width;
  const float u0 = static_cast<float>(g.u0), inv_res_h = static_cast<float>(1 / g.res_h);
  const float u_end = static_cast<float>(width) - 0.5f;
  const float wrap = static_cast<float>(g.wrapping_columns());
  // A few probes a row decide; only a sweep off the grid pays for the whole pass.
  bool on_grid = true;
  for (int row = 0; row < g.height && on_grid; ++row) {
    on_grid =
        sampled_on_grid(azimuth, image.index.ptr<std::int32_t>(row),
                        image.count.ptr<std::int32_t>(row), width, u0, inv_res_h, u_end, wrap);
  }
  if (on_grid) {
    image.column_offset.release();
    return;
  }
  image.column_offset.create(g.height, width, CV_32F);
  for (int row = 0; row < g.height; ++row) {
    const auto* index = image.index.ptr<std::int32_t>(row);
    const auto* count = image.count.ptr<std::int32_t>(row);
    auto* offset = image.column_offset.ptr<float>(row);
    for (int c = 0; c < width; ++c)
      offset[c] = count[c] == 1
                      ? offset_from_centre(azimuth[index[c]], c, u0, inv_res_h, u_end, wrap)
                      : 0.f;
  }
}

void intensity_at_centres(const ProjectedImage& image, cv::Mat& out, cv::Rect within) {
  image.intensity.copyTo(out);
  if (image.column_offset.empty()) return;
  const int width = image.intensity.cols;
  within &= cv::Rect(0, 0, width, image.intensity.rows);
  for (int row = within.y; row < within.y + within.height; ++row) {
    const auto* count = image.count.ptr<std::int32_t>(row);
    const auto* offset = image.column_offset.ptr<float>(row);
    const auto* original = image.intensity.ptr<float>(row);
    auto* value = out.ptr<float>(row);
    for (int c = within.x; c < within.x + within.width; ++c) {
      const float d = offset[c];
      if (count[c] != 1 || std::abs(d) <= kColumnOffsetTolerance) continue;
      // The neighbour on the centre's other side: the centre lies between the two samples.
      const int n = d > 0 ? c - 1 : c + 1;
      if (n < 0 || n >= width || count[n] == 0) continue;
      const float at = static_cast<float>(c) + d, neighbour_at = static_cast<float>(n) + offset[n];
      if ((neighbour_at - static_cast<float>(c)) * d >= 0) continue;  // both on one side
      const float w = -d / (neighbour_at - at);  // (c - at) / (neighbour_at - at), in (0, 1)
      value[c] = original[c] + w * (original[n] - original[c]);
    }
  }
}

std::optional<cv::Rect2d> box_around(const Vec2* points, std::size_t count) {
  double u_lo = 1e300, u_hi = -1e300, v_lo = 1e300, v_hi = -1e300;
  for (const Vec2* p = points; p != points + count; ++p) {
    if (!p->allFinite()) return std::nullopt;
    u_lo = std::min(u_lo, p->x());
    u_hi = std::max(u_hi, p->x());
    v_lo = std::min(v_lo, p->y());
    v_hi = std::max(v_hi, p->y());
  }
  return cv::Rect2d(u_lo, v_lo, u_hi - u_lo, v_hi - v_lo);
}

ColumnOffsets column_offsets_in_box(const ProjectedImage& image, const Vec2* corners,
                                    std::size_t count) {
  ColumnOffsets out;
  if (image.column_offset.empty() || count == 0) return out;
  const std::optional<cv::Rect2d> box = box_around(corners, count);
  if (!box) return out;
  const ImageGeometry& g = image.geometry;
  const int r0 = std::max(0, static_cast<int>(std::floor(box->y))),
            r1 = std::min(g.height - 1, static_cast<int>(std::ceil(box->y + box->height)));
  const int c0 = static_cast<int>(std::floor(box->x)),
            c1 = static_cast<int>(std::ceil(box->x + box->width));
  double sum = 0;
  int n = 0;
  bool any_row = false;
  for (int row = r0; row <= r1; ++row) {
    const auto* pixels = image.count.ptr<std::int32_t>(row);
    const auto* offset = image.column_offset.ptr<float>(row);
    double row_sum = 0;
    int row_n = 0;
    for (int col = c0; col <= c1; ++col) {
      const int c = g.wrap_column(col);  // a box across a full circle's seam
      if (c < 0 || c >= g.width || pixels[c] != 1) continue;
      row_sum += offset[c];
      ++row_n;
    }
    if (row_n == 0) continue;
    const double row_mean = row_sum / row_n;
    out.lowest_row = any_row ? std::min(out.lowest_row, row_mean) : row_mean;
    out.highest_row = any_row ? std::max(out.highest_row, row_mean) : row_mean;
    any_row = true;
    sum += row_sum;
    n += row_n;
  }
  out.mean = n > 0 ? sum / n : 0;
  return out;
}

void move_to_samples(const ProjectedImage& image, std::vector<Vec2>& corners,
                     std::vector<Vec2>& outline) {
  if (image.column_offset.empty()) return;
  const double offset = column_offsets_in_box(image, corners.data(), corners.size()).mean;
  for (Vec2& p : corners) p.x() += offset;
  for (Vec2& p : outline) p.x() += offset;
}

void move_hull_to_samples(const ProjectedImage& image, std::array<Vec2, 4>& quad) {
  const ColumnOffsets o = column_offsets_in_box(image, quad.data(), quad.size());
  double x_lo = quad[0].x(), x_hi = quad[0].x();
  for (const Vec2& p : quad) {
    x_lo = std::min(x_lo, p.x());
    x_hi = std::max(x_hi, p.x());
  }
  const double middle = 0.5 * (x_lo + x_hi), half_width = 0.5 * (x_hi - x_lo);
  const double mid_offset = 0.5 * (o.highest_row + o.lowest_row),
               half_spread = 0.5 * (o.highest_row - o.lowest_row);
  for (Vec2& p : quad) {
    // -1 at the leftmost corner, +1 at the rightmost.
    const double side = half_width > 0 ? std::clamp((p.x() - middle) / half_width, -1.0, 1.0) : 0;
    p.x() += mid_offset - side * half_spread;
  }
}

}  // namespace iilfm::detail
