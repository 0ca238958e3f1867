#include "candidate_sides.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace iilfm::detail {

namespace {

// The median of `v` (not empty), the mean of the middle two for an even count.
double median_of(std::vector<double>& v) {
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

}  // namespace

std::array<int, 4> side_facings(const std::array<Vec2, 4>& corners) {
  Vec2 centre = Vec2::Zero();
  for (const Vec2& p : corners) centre += 0.25 * p;
  std::array<int, 4> facing{};
  for (std::size_t k = 0; k < 4; ++k) {
    const Vec2& a = corners[k];
    const Vec2& b = corners[(k + 1) % 4];
    const Vec2 d = b - a;
    if (!(std::abs(d.y()) > std::abs(d.x()))) continue;  // a top or bottom side
    facing[k] = 0.5 * (a.x() + b.x()) > centre.x() ? 1 : -1;
  }
  return facing;
}

std::array<Vec2, 4> sides_moved(const std::array<Vec2, 4>& corners, double left, double right) {
  const std::array<int, 4> facing = side_facings(corners);
  std::array<Vec2, 4> out = corners;
  for (std::size_t k = 0; k < 4; ++k) {
    if (facing[k] == 0) continue;
    const double by = facing[k] > 0 ? right : left;
    out[k].x() += by;
    out[(k + 1) % 4].x() += by;
  }
  return out;
}

std::optional<std::array<Vec2, 4>> squared_left_right_sides(const std::array<Vec2, 4>& corners,
                                                            double column_angle, double row_angle) {
  const std::array<int, 4> facing = side_facings(corners);
  // In angle units, where right angles are right.
  const Vec2 scale(column_angle, row_angle);
  std::array<Vec2, 4> p;
  for (std::size_t k = 0; k < 4; ++k) p[k] = corners[k].cwiseProduct(scale);
  // The top and bottom sides' mean direction, both taken left to right.
  Vec2 along = Vec2::Zero();
  int across = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    if (facing[k] != 0) continue;
    Vec2 d = p[(k + 1) % 4] - p[k];
    if (d.x() < 0) d = -d;
    if (!(d.norm() > 0)) return std::nullopt;
    along += d.normalized();
    ++across;
  }
  if (across != 2 || !(along.norm() > 0)) return std::nullopt;
  const Vec2 up(-along.y(), along.x());  // the left and right sides' new direction
  // Each corner moves along its top or bottom side's line to where the side through its left or
  // right side's middle, along `up`, meets it.
  std::array<Vec2, 4> out = p;
  for (std::size_t k = 0; k < 4; ++k) {
    if (facing[k] == 0) continue;
    const Vec2 middle = 0.5 * (p[k] + p[(k + 1) % 4]);
    // Corner k lies on side k - 1, corner k + 1 on side k + 1: both top or bottom sides.
    for (const std::size_t corner : {k, (k + 1) % 4}) {
      const std::size_t other = corner == k ? (k + 3) % 4 : (k + 2) % 4;  // its side's far end
      const Vec2 d = p[corner] - p[other];
      // other + s d = middle + t up
      const double det = d.x() * -up.y() - d.y() * -up.x();
      if (!(std::abs(det) > 1e-12 * d.norm())) return std::nullopt;
      const Vec2 rhs = middle - p[other];
      const double s = (rhs.x() * -up.y() - rhs.y() * -up.x()) / det;
      out[corner] = p[other] + s * d;
    }
  }
  for (Vec2& q : out) q = q.cwiseQuotient(scale);
  return out;
}

std::optional<std::array<Vec2, 4>> measured_side_columns(const std::array<Vec2, 4>& corners,
                                                         const ProjectedImage& image,
                                                         const cv::Mat& intensity, double black,
                                                         double white, double max_shift_px) {
  if (!(white > black)) return std::nullopt;
  const ImageGeometry& g = image.geometry;
  const double mid = 0.5 * (black + white);
  const std::array<int, 4> facing = side_facings(corners);
  // The level of pixel (c, r), nothing where unobserved or outside.
  const auto level = [&](int c, int r) -> std::optional<double> {
    c = g.wrap_column(c);
    if (!g.contains_pixel(c, r) || !image.observed(c, r)) return std::nullopt;
    return static_cast<double>(intensity.at<float>(r, c));
  };
  // Where pixel (c, r)'s sample lies (ProjectedImage::column_offset), in columns.
  const auto position = [&](int c, int r) {
    const int wrapped = g.wrap_column(c);
    if (image.column_offset.empty() || !g.contains_pixel(wrapped, r)) return double(c);
    return c + static_cast<double>(image.column_offset.at<float>(r, wrapped));
  };
  std::array<Vec2, 4> out = corners;
  int sides = 0;
  for (int k = 0; k < 4; ++k) {
    const Vec2 a = corners[static_cast<std::size_t>(k)];
    const Vec2 b = corners[static_cast<std::size_t>((k + 1) % 4)];
    const Vec2 d = b - a;
    if (facing[static_cast<std::size_t>(k)] == 0) continue;  // a top or bottom side
    ++sides;
    const double outwards = facing[static_cast<std::size_t>(k)];
    // The rows whose centres lie on the side, half a pixel in from its ends.
    const int first_row = static_cast<int>(std::ceil(std::min(a.y(), b.y()) + 0.5));
    const int last_row = static_cast<int>(std::floor(std::max(a.y(), b.y()) - 0.5));
    std::vector<double> shifts;
    for (int r = first_row; r <= last_row; ++r) {
      const double side_x = a.x() + d.x() * (r - a.y()) / d.y();
      // The row's pixels from a pixel and a half inside the side to as far outside: from the
      // darkest outwards, the first to reach the level midway between it and the brightest
      // beyond it. The levels are the row's own: the marker's white, read from its cells, is
      // lowered by the mixed pixels along the cell edges.
      const int start = static_cast<int>(std::lround(side_x - outwards * (max_shift_px + 0.5)));
      const int count = static_cast<int>(std::ceil(2 * max_shift_px + 2));
      std::vector<std::optional<double>> row(static_cast<std::size_t>(count));
      int darkest = -1;
      for (int j = 0; j < count; ++j) {
        row[static_cast<std::size_t>(j)] = level(start + static_cast<int>(outwards) * j, r);
        const auto& v = row[static_cast<std::size_t>(j)];
        if (v && (darkest < 0 || *v < *row[static_cast<std::size_t>(darkest)])) darkest = j;
      }
      if (darkest < 0) continue;
      const double dark = *row[static_cast<std::size_t>(darkest)];
      double bright = dark;
      for (int j = darkest + 1; j < count; ++j)
        if (const auto& v = row[static_cast<std::size_t>(j)]) bright = std::max(bright, *v);
      // The step must span half the marker's contrast: a row through white data cells or wall
      // alone says nothing of the edge.
      if (bright - dark < 0.5 * (white - black) || dark > mid) continue;
      const double row_mid = 0.5 * (dark + bright);
      const auto column = [&](int j) { return start + static_cast<int>(outwards) * j; };
      double previous = dark;
      double previous_at = position(column(darkest), r);
      for (int j = darkest + 1; j < count; ++j) {
        const auto& v = row[static_cast<std::size_t>(j)];
        if (!v) continue;
        const double at = position(column(j), r);
        if (*v >= row_mid) {
          shifts.push_back(previous_at +
                           (at - previous_at) * (row_mid - previous) / (*v - previous) - side_x);
          break;
        }
        previous = *v;
        previous_at = at;
      }
    }
    if (shifts.size() < 2) return std::nullopt;
    const double shift = std::clamp(median_of(shifts), -max_shift_px, max_shift_px);
    out[static_cast<std::size_t>(k)].x() += shift;
    out[static_cast<std::size_t>((k + 1) % 4)].x() += shift;
  }
  if (sides != 2) return std::nullopt;
  return out;
}

}  // namespace iilfm::detail
