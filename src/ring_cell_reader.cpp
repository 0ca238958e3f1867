#include "ring_cell_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "cpu_clones.hpp"
#include "rank_of_few.hpp"

namespace iilfm::detail {

namespace {

struct TangentFrame {
  Vec3 d, right, up;
  // Tangent-plane coordinates of a direction; b grows downwards like image rows.
  Vec2 of(const Vec3& ray) const {
    const double z = ray.dot(d);
    return Vec2(ray.dot(right) / z, -ray.dot(up) / z);
  }
  Vec3 ray(const Vec2& t) const { return (d + t.x() * right - t.y() * up).normalized(); }
};

// Column `u` moved by whole turns of a full-circle image to lie nearest `reference` (a quad across
// the seam has columns past the last one); `u` itself otherwise.
double column_near(const ImageGeometry& g, double u, double reference) {
  if (!g.full_circle()) return u;
  return u + std::round((reference - u) / g.columns_per_turn()) * g.columns_per_turn();
}

cv::Point2d apply(const cv::Matx33d& H, double x, double y) {
  const cv::Vec3d p = H * cv::Vec3d(x, y, 1);
  return {p[0] / p[2], p[1] / p[2]};
}

double median(std::vector<float>& v) {
  return value_of_rank_among_few(v.data(), v.size(), v.size() / 2);
}

}  // namespace

bool columns_are_coarse(const ImageGeometry& g) { return g.res_h > kCoarseColumnsRatio * g.res_v; }

MarkerSamples::MarkerSamples(const std::array<Vec2, 4>& corners_px, const ProjectedImage& image,
                             const cv::Mat& intensity, const CellCodeBook& book) {
  const ImageGeometry& g = image.geometry;
  std::array<Vec3, 4> rays;
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    if (!corners_px[k].allFinite()) return;
    rays[k] = g.ray(corners_px[k]);
    sum += rays[k];
  }
  TangentFrame frame;
  frame.d = sum.normalized();
  const Vec3 z(0, 0, 1);
  if (std::abs(frame.d.dot(z)) > 0.99) return;  // near the zenith: no image up
  frame.up = (z - frame.d.dot(z) * frame.d).normalized();
  frame.right = frame.up.cross(frame.d);
  if (columns_are_coarse(g)) {  // a quarter turn: (a, b) -> (b, -a), the same rays
    const Vec3 right = frame.right;
    frame.right = -frame.up;
    frame.up = right;
  }
  const float n = static_cast<float>(book.border_width());
  const std::vector<cv::Point2f> square = {{0, 0}, {n, 0}, {n, n}, {0, n}};
  std::vector<cv::Point2f> quad;
  for (const Vec3& r : rays) {
    const Vec2 t = frame.of(r);
    quad.emplace_back(static_cast<float>(t.x()), static_cast<float>(t.y()));
  }
  const double area = std::abs(cv::contourArea(quad));
  if (!(area > 1e-12)) return;
  const cv::Matx33d cell_to_tangent = cv::getPerspectiveTransform(square, quad);
  quad_ = quad;
  view_ = frame.d;
  right_ = frame.right;
  up_ = frame.up;
  start_ = book.border_start();
  n_ = book.border_width();
  cell_height_ = std::sqrt(area) / book.border_width();  // whatever the quad's turn

  // Pixels around the printed image (one more cell each way, for the shifts tried), their columns
  // on the corners' side of a full-circle image's seam (a quad across it has corners past the
  // last column).
  const double lo = -start_ - 1, hi = book.total_width() - start_ + 1;
  u_corners_ =
      0.25 * (corners_px[0].x() + corners_px[1].x() + corners_px[2].x() + corners_px[3].x());
  double u_min = 1e300, u_max = -1e300, v_min = 1e300, v_max = -1e300;
  for (const auto& [x, y] : {std::pair{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}}) {
    const cv::Point2d t = apply(cell_to_tangent, x, y);
    const Vec2 px = g.pixel_of_point(frame.ray(Vec2(t.x, t.y)));
    const double u = column_near(g, px.x(), u_corners_);
    u_min = std::min(u_min, u);
    u_max = std::max(u_max, u);
    v_min = std::min(v_min, px.y());
    v_max = std::max(v_max, px.y());
  }
  // A quad that does not fit the image's turn is not a marker.
  if (!(u_max - u_min < 0.5 * g.columns_per_turn())) return;
  const int row_lo = std::max(0, static_cast<int>(std::floor(v_min)));
  const int row_hi = std::min(g.height - 1, static_cast<int>(std::ceil(v_max)));
  const int col_lo = static_cast<int>(std::floor(u_min)),
            col_hi = static_cast<int>(std::ceil(u_max));
  if (col_hi < col_lo) return;
  // Pixel directions as ImageGeometry::ray computes them, from per-column and per-row tables.
  std::vector<double> cos_az(static_cast<std::size_t>(col_hi - col_lo + 1)), sin_az(cos_az.size());
  for (int col = col_lo; col <= col_hi; ++col) {
    const double azimuth = g.azimuth_of_u(col);
    cos_az[static_cast<std::size_t>(col - col_lo)] = std::cos(azimuth);
    sin_az[static_cast<std::size_t>(col - col_lo)] = std::sin(azimuth);
  }
  const std::size_t most =
      static_cast<std::size_t>(std::max(0, row_hi - row_lo + 1)) * cos_az.size();
  const float* offsets = image.column_offset.empty() ? nullptr : image.column_offset.ptr<float>();
  a_.reserve(most);
  b_.reserve(most);
  intensity_.reserve(most);
  for (int row = row_lo; row <= row_hi; ++row) {
    const double elevation = g.elevation_of_v(row);
    const double cos_el = std::cos(elevation), sin_el = std::sin(elevation);
    for (int col = col_lo; col <= col_hi; ++col) {
      const int c = g.wrap_column(col);
      if (!g.contains_pixel(c, row) || !image.observed(c, row)) continue;
      // The pixel's own direction, at the unwrapped column so it lies beside the marker; its
      // sample's own where it lies off the column grid.
      const std::size_t k = static_cast<std::size_t>(col - col_lo);
      double cos_a = cos_az[k], sin_a = sin_az[k];
      if (offsets) {
        // d columns right is delta = d * res_h less azimuth; |delta| < 0.01 rad, so two terms of
        // its cosine and sine are exact to 1e-10.
        const double delta = offsets[static_cast<std::ptrdiff_t>(row) * g.width + c] * g.res_h;
        const double cos_d = 1 - 0.5 * delta * delta, sin_d = delta * (1 - delta * delta / 6);
        cos_a = cos_az[k] * cos_d + sin_az[k] * sin_d;
        sin_a = sin_az[k] * cos_d - cos_az[k] * sin_d;
      }
      const Vec2 t = frame.of(Vec3(cos_el * cos_a, cos_el * sin_a, sin_el));
      a_.push_back(t.x());
      b_.push_back(t.y());
      intensity_.push_back(intensity.at<float>(row, c));
    }
  }
}

namespace {

// The homography from the unit square's corners (0,0), (1,0), (1,1), (0,1) to `q` (Heckbert's
// closed form, "Fundamentals of Texture Mapping and Image Warping", 1989, sec. 2.2.3).
cv::Matx33d unit_square_to_quad(const cv::Point2d q[4]) {
  const double sx = q[0].x - q[1].x + q[2].x - q[3].x, sy = q[0].y - q[1].y + q[2].y - q[3].y;
  double g = 0, h = 0;
  if (sx != 0 || sy != 0) {
    const double dx1 = q[1].x - q[2].x, dx2 = q[3].x - q[2].x;
    const double dy1 = q[1].y - q[2].y, dy2 = q[3].y - q[2].y;
    const double det = dx1 * dy2 - dx2 * dy1;
    g = (sx * dy2 - dx2 * sy) / det;
    h = (dx1 * sy - sx * dy1) / det;
  }
  const double a = q[1].x - q[0].x + g * q[1].x, b = q[3].x - q[0].x + h * q[3].x;
  const double d = q[1].y - q[0].y + g * q[1].y, e = q[3].y - q[0].y + h * q[3].y;
  return cv::Matx33d(a, b, q[0].x, d, e, q[0].y, g, h, 1);
}

// Maps the tangent plane to printed cells when the quad's top side moves by `top` and its bottom
// side by `bottom` (tangent units, down positive): the inverse of the square-to-quad map, scaled to
// the square's `n` cells. The search over placings calls this hundreds of times per quad, in closed
// form (an 8 x 8 solve, as cv::getPerspectiveTransform does it, took a seventh of the search).
cv::Matx33d shifted_tangent_to_cell(const std::vector<cv::Point2f>& corners, float top,
                                    float bottom, int n) {
  // The corners above the quad's middle form its top, whichever corner comes first.
  const float middle = 0.25f * (corners[0].y + corners[1].y + corners[2].y + corners[3].y);
  cv::Point2d quad[4];
  for (int k = 0; k < 4; ++k) {
    quad[k] = cv::Point2d(corners[k].x, corners[k].y + (corners[k].y < middle ? top : bottom));
  }
  const cv::Matx33d to_quad = unit_square_to_quad(quad);
  const cv::Matx33d to_unit = to_quad.inv(cv::DECOMP_LU);
  const cv::Matx33d scale(n, 0, 0, 0, n, 0, 0, 0, 1);
  const cv::Matx33d H = scale * to_unit;
  return H * (1.0 / H(2, 2));
}

}  // namespace

std::array<Vec2, 4> MarkerSamples::corners_at(double shift_top, double shift_bottom,
                                              const ImageGeometry& g) const {
  std::array<Vec2, 4> corners;
  corners.fill(Vec2::Zero());
  if (quad_.size() != 4) return corners;
  const TangentFrame frame{view_, right_, up_};
  // The corners above the quad's middle form its top, as in shifted_tangent_to_cell.
  const float middle = 0.25f * (quad_[0].y + quad_[1].y + quad_[2].y + quad_[3].y);
  for (int k = 0; k < 4; ++k) {
    const double shift = quad_[k].y < middle ? shift_top : shift_bottom;
    const Vec2 t(quad_[k].x, quad_[k].y + shift * cell_height_);
    corners[k] = g.pixel_of_point(frame.ray(t));
    corners[k].x() = column_near(g, corners[k].x(), u_corners_);
  }
  return corners;
}

void MarkerSamples::place(double shift_top, double shift_bottom, std::vector<Placed>& out) const {
  out.clear();
  if (a_.empty()) return;
  const cv::Matx33d H =
      shifted_tangent_to_cell(quad_, static_cast<float>(shift_top * cell_height_),
                              static_cast<float>(shift_bottom * cell_height_), n_);
  for (std::size_t i = 0; i < a_.size(); ++i) {
    const cv::Point2d c = apply(H, a_[i], b_[i]);
    out.push_back({c.x + start_, c.y + start_, intensity_[i]});
  }
}

namespace {

// A homography H from the tangent plane to printed cells, offset by `start`: where a sample falls
// on the print, in cells. Its coefficients in locals, so the loops using it vectorise.
struct PrintPlacement {
  double h00, h01, h02, h10, h11, h12, h20, h21, h22, start;
  PrintPlacement(const cv::Matx33d& H, double start_cell)
      : h00(H(0, 0)),
        h01(H(0, 1)),
        h02(H(0, 2)),
        h10(H(1, 0)),
        h11(H(1, 1)),
        h12(H(1, 2)),
        h20(H(2, 0)),
        h21(H(2, 1)),
        h22(H(2, 2)),
        start(start_cell) {}
  void at(double a, double b, double& x, double& y) const {
    const double inverse_w = 1.0 / (h20 * a + h21 * b + h22);
    x = (h00 * a + h01 * b + h02) * inverse_w + start;
    y = (h10 * a + h11 * b + h12) * inverse_w + start;
  }
};

// The printed cell each sample falls in under the homography H (tangent plane to cells, offset by
// `start`), as read_cells places it: row * T + col, or -1 outside the T x T print or off the
// middle `2 half` of its cell. No branches, so it vectorises; the search over placings runs it
// hundreds of times per quad.
IILFM_AVX2_CLONES void cells_of_samples(const cv::Matx33d& H, double start, int T, double half,
                                        const double* __restrict a, const double* __restrict b,
                                        std::size_t n, std::int32_t* __restrict cell) {
  const PrintPlacement placement(H, start);
  const double width = T;
  for (std::size_t i = 0; i < n; ++i) {
    double x, y;
    placement.at(a[i], b[i], x, y);
    const bool inside = (x >= 0) & (y >= 0) & (x < width) & (y < width);  // false for NaN
    // Clamped before the conversion, which is undefined out of int's range (NaN gives 0).
    const double xc = std::min(std::max(0.0, x), width), yc = std::min(std::max(0.0, y), width);
    const auto col = static_cast<std::int32_t>(xc), row = static_cast<std::int32_t>(yc);
    const bool central = (std::abs(x - col - 0.5) <= half) & (std::abs(y - row - 0.5) <= half);
    cell[i] = (inside & central) ? row * T + col : -1;
  }
}

// Where each sample falls on the print under the homography H (tangent plane to cells, offset by
// `start`), in cells, as cells_of_samples places it; a loop that vectorises.
IILFM_AVX2_CLONES void places_of_samples(const cv::Matx33d& H, double start,
                                         const double* __restrict a, const double* __restrict b,
                                         std::size_t n, double* __restrict x_out,
                                         double* __restrict y_out) {
  const PrintPlacement placement(H, start);
  for (std::size_t i = 0; i < n; ++i) placement.at(a[i], b[i], x_out[i], y_out[i]);
}

}  // namespace

void MarkerSamples::sum_cells(double shift_top, double shift_bottom, const CellCodeBook& book,
                              double central_fraction, bool data_cells, Scratch& scratch) const {
  const cv::Matx33d H =
      shifted_tangent_to_cell(quad_, static_cast<float>(shift_top * cell_height_),
                              static_cast<float>(shift_bottom * cell_height_), n_);
  const int T = book.total_width();
  scratch.sum.assign(static_cast<std::size_t>(T) * T, 0);
  scratch.count.assign(scratch.sum.size(), 0);
  scratch.black.clear();
  scratch.white.clear();
  scratch.cell.resize(a_.size());
  cells_of_samples(H, start_, T, 0.5 * central_fraction, a_.data(), b_.data(), a_.size(),
                   scratch.cell.data());
  // Samples come row by row, so runs of them fall in one cell: a run's sum is kept in a register
  // (the same additions in order) rather than added through memory sample by sample.
  const std::size_t n = a_.size();
  for (std::size_t k = 0; k < n;) {
    const std::int32_t i = scratch.cell[k];
    const int role = i < 0 ? 0 : book.cell_role(i);
    if (i < 0 || (role >= 0 && !data_cells)) {  // off the print or a cell's middle; data cell
      ++k;
      continue;
    }
    std::vector<float>* level = role == CellCodeBook::kFixedBlack   ? &scratch.black
                                : role == CellCodeBook::kFixedWhite ? &scratch.white
                                                                    : nullptr;
    double sum = scratch.sum[static_cast<std::size_t>(i)];
    int count = scratch.count[static_cast<std::size_t>(i)];
    for (; k < n && scratch.cell[k] == i; ++k) {
      sum += intensity_[k];
      ++count;
      if (level) level->push_back(intensity_[k]);
    }
    scratch.sum[static_cast<std::size_t>(i)] = sum;
    scratch.count[static_cast<std::size_t>(i)] = count;
  }
}

double MarkerSamples::fixed_agreement(double shift_top, double shift_bottom,
                                      const CellCodeBook& book, const CellReadOptions& options,
                                      Scratch& scratch) const {
  if (a_.empty()) return -1;
  // As read_cells does with place()'s output, for the fixed cells only.
  sum_cells(shift_top, shift_bottom, book, options.central_fraction, false, scratch);
  if (scratch.black.empty() || scratch.white.empty()) return -1;
  const int T = book.total_width();
  const double black = median(scratch.black), white = median(scratch.white);
  const double contrast = white - black;
  if (!(contrast > 0)) return -1;
  const double threshold = black + 0.5 * contrast;
  int black_cells = 0, white_cells = 0, fixed = 0, agreeing = 0;
  for (int row = 0; row < T; ++row) {
    for (int col = 0; col < T; ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * T + col;
      if (scratch.count[i] == 0) continue;
      const bool is_white = book.cell_role(col, row) == CellCodeBook::kFixedWhite;
      (is_white ? white_cells : black_cells)++;
      ++fixed;
      if ((scratch.sum[i] / scratch.count[i] > threshold) == is_white) ++agreeing;
    }
  }
  const bool ok = black_cells >= options.min_fixed_cells &&
                  white_cells >= options.min_fixed_cells &&
                  agreeing >= options.min_fixed_agreement * fixed;
  return ok ? static_cast<double>(agreeing) / fixed : -1;
}

MarkerSamples MarkerSamples::fixed_cell_samples(double lowest, double highest,
                                                const CellCodeBook& book,
                                                double central_fraction) const {
  return fixed_cell_samples({{lowest, lowest}, {highest, highest}}, book, central_fraction);
}

MarkerSamples MarkerSamples::fixed_cell_samples(ShiftRange top, ShiftRange bottom,
                                                const CellCodeBook& book,
                                                double central_fraction) const {
  return fixed_cell_samples({{top.lowest, bottom.lowest},
                             {top.lowest, bottom.highest},
                             {top.highest, bottom.lowest},
                             {top.highest, bottom.highest}},
                            book, central_fraction);
}

MarkerSamples MarkerSamples::fixed_cell_samples(
    const std::vector<std::pair<double, double>>& bounding_placings, const CellCodeBook& book,
    double central_fraction) const {
  MarkerSamples out;
  out.quad_ = quad_;
  out.cell_height_ = cell_height_;
  out.start_ = start_;
  out.n_ = n_;
  if (a_.empty()) return out;
  constexpr double kRounding = 0.01;  // cells: far above the float rounding of the quad's shift
  constexpr double kMostCells = 4;    // a longer track (a degenerate quad) keeps its sample
  const int T = book.total_width();
  const double half = 0.5 * central_fraction;
  // Each sample's box of places over the bounding placings.
  const std::size_t n = a_.size();
  thread_local std::vector<double> x, y, x_lo, x_hi, y_lo, y_hi;
  thread_local std::vector<char> placed;  // 0 once a place is not finite: then no bound
  placed.assign(n, 1);
  x.resize(n);
  y.resize(n);
  x_lo.assign(n, std::numeric_limits<double>::infinity());
  y_lo.assign(n, std::numeric_limits<double>::infinity());
  x_hi.assign(n, -std::numeric_limits<double>::infinity());
  y_hi.assign(n, -std::numeric_limits<double>::infinity());
  for (const auto& [shift_top, shift_bottom] : bounding_placings) {
    places_of_samples(shifted_tangent_to_cell(quad_, static_cast<float>(shift_top * cell_height_),
                                              static_cast<float>(shift_bottom * cell_height_), n_),
                      start_, a_.data(), b_.data(), n, x.data(), y.data());
    for (std::size_t i = 0; i < n; ++i) {
      placed[i] &= static_cast<char>(std::isfinite(x[i]) && std::isfinite(y[i]));
      x_lo[i] = std::min(x_lo[i], x[i]);
      x_hi[i] = std::max(x_hi[i], x[i]);
      y_lo[i] = std::min(y_lo[i], y[i]);
      y_hi[i] = std::max(y_hi[i], y[i]);
    }
  }
  // Whether the middle of a fixed cell lies within [lo, hi] x [top, bottom] (print cells).
  const double first_middle = 0.5 - half, last_middle = T - 0.5 + half;
  const auto meets_fixed_cell = [&](double lo, double hi, double top, double bottom) {
    if (!(hi - lo < kMostCells && bottom - top < kMostCells)) return true;  // NaN too
    if (hi < first_middle || lo > last_middle || bottom < first_middle || top > last_middle)
      return false;  // off the print's cells
    const int c0 = std::max(0, static_cast<int>(std::floor(lo))),
              c1 = std::min(T - 1, static_cast<int>(std::floor(hi)));
    const int r0 = std::max(0, static_cast<int>(std::floor(top))),
              r1 = std::min(T - 1, static_cast<int>(std::floor(bottom)));
    for (int row = r0; row <= r1; ++row) {
      if (row + 0.5 + half < top || row + 0.5 - half > bottom) continue;
      for (int col = c0; col <= c1; ++col) {
        if (col + 0.5 + half < lo || col + 0.5 - half > hi) continue;
        if (book.cell_role(col, row) < 0) return true;
      }
    }
    return false;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (placed[i] && !meets_fixed_cell(x_lo[i] - kRounding, x_hi[i] + kRounding,
                                       y_lo[i] - kRounding, y_hi[i] + kRounding))
      continue;  // else kept: no bound
    out.a_.push_back(a_[i]);
    out.b_.push_back(b_[i]);
    out.intensity_.push_back(intensity_[i]);
  }
  return out;
}

namespace {

// The reading from each cell's sum and count of central samples and the fixed cells' samples:
// black and white levels (medians), the threshold half-way, the fixed cells' agreement and the
// data bits, with cells near the threshold as erasures.
CellReading cells_from_sums(const std::vector<double>& sum, const std::vector<int>& count,
                            std::vector<float>& black, std::vector<float>& white,
                            const CellCodeBook& book, const CellReadOptions& options) {
  const int T = book.total_width();
  CellReading out;
  if (black.empty() || white.empty()) return out;
  out.black = median(black);
  out.white = median(white);
  const double contrast = out.white - out.black;
  if (!(contrast > 0)) return out;
  const double threshold = out.black + 0.5 * contrast;
  int black_cells = 0, white_cells = 0;
  for (int row = 0; row < T; ++row)
    for (int col = 0; col < T; ++col) {
      const std::size_t i = static_cast<std::size_t>(row) * T + col;
      if (count[i] == 0) continue;
      const double mean = sum[i] / count[i];
      const int role = book.cell_role(col, row);
      if (role < 0) {
        const bool is_white = role == CellCodeBook::kFixedWhite;
        (is_white ? white_cells : black_cells)++;
        ++out.fixed_cells;
        if ((mean > threshold) == is_white) ++out.fixed_agreeing;
        continue;
      }
      if (std::abs(mean - threshold) < options.ambiguous_fraction * contrast) continue;
      out.bits.known |= std::uint64_t{1} << role;
      if (mean > threshold) out.bits.white |= std::uint64_t{1} << role;
    }
  out.levels_ok = black_cells >= options.min_fixed_cells &&
                  white_cells >= options.min_fixed_cells &&
                  out.fixed_agreeing >= options.min_fixed_agreement * out.fixed_cells;
  return out;
}

}  // namespace

CellReading MarkerSamples::read(double shift_top, double shift_bottom, const CellCodeBook& book,
                                const CellReadOptions& options, Scratch& scratch) const {
  if (a_.empty()) return {};
  sum_cells(shift_top, shift_bottom, book, options.central_fraction, true, scratch);
  return cells_from_sums(scratch.sum, scratch.count, scratch.black, scratch.white, book, options);
}

CellReading read_cells(const std::vector<MarkerSamples::Placed>& placed, const CellCodeBook& book,
                       const CellReadOptions& options) {
  const int T = book.total_width();
  std::vector<double> sum(static_cast<std::size_t>(T) * T, 0);
  std::vector<int> count(sum.size(), 0);
  std::vector<float> black, white;
  const double half = 0.5 * options.central_fraction;
  for (const MarkerSamples::Placed& p : placed) {
    if (!(p.col >= 0 && p.row >= 0 && p.col < T && p.row < T)) continue;
    const int col = static_cast<int>(p.col), row = static_cast<int>(p.row);
    if (std::abs(p.col - col - 0.5) > half || std::abs(p.row - row - 0.5) > half) continue;
    const std::size_t i = static_cast<std::size_t>(row) * T + col;
    sum[i] += p.intensity;
    ++count[i];
    const int role = book.cell_role(col, row);
    if (role == CellCodeBook::kFixedBlack) black.push_back(p.intensity);
    if (role == CellCodeBook::kFixedWhite) white.push_back(p.intensity);
  }
  return cells_from_sums(sum, count, black, white, book, options);
}

}  // namespace iilfm::detail
