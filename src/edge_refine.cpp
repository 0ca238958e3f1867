#include "iilfm/edge_refine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

namespace iilfm {

namespace {

// Intensity at continuous image coordinates (pixel centres at integers): bilinear over the
// observed ones of the four neighbouring pixels, renormalised; nothing when they hold under a
// quarter of the weight (rosette scans leave holes).
std::optional<double> intensity_at(const ProjectedImage& image, const Vec2& uv) {
  const ImageGeometry& g = image.geometry;
  const int c0 = static_cast<int>(std::floor(uv.x())), r0 = static_cast<int>(std::floor(uv.y()));
  const double fu = uv.x() - c0, fv = uv.y() - r0;
  double sum = 0, weight = 0;
  if (c0 >= 0 && r0 >= 0 && c0 + 1 < g.width && r0 + 1 < g.height) {
    // All four inside the image (the common case): the same sums, read through row pointers.
    for (int dr = 0; dr <= 1; ++dr) {
      const std::uint8_t* seen = image.mask.ptr<std::uint8_t>(r0 + dr) + c0;
      const float* value = image.intensity.ptr<float>(r0 + dr) + c0;
      for (int dc = 0; dc <= 1; ++dc) {
        if (!seen[dc]) continue;
        const double w = (dc ? fu : 1 - fu) * (dr ? fv : 1 - fv);
        sum += w * value[dc];
        weight += w;
      }
    }
    if (weight < 0.25) return std::nullopt;
    return sum / weight;
  }
  for (int dr = 0; dr <= 1; ++dr) {
    for (int dc = 0; dc <= 1; ++dc) {
      const int c = g.wrap_column(c0 + dc), r = r0 + dr;  // across the seam of a full circle
      if (!g.contains_pixel(c, r) || !image.observed(c, r)) continue;
      const double w = (dc ? fu : 1 - fu) * (dr ? fv : 1 - fv);
      sum += w * image.intensity.at<float>(r, c);
      weight += w;
    }
  }
  if (weight < 0.25) return std::nullopt;
  return sum / weight;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// One side of the quad, from a to b, with its outward normal and the length of one cell along
// that normal (pixels; rows and columns may differ in angle).
struct Side {
  Vec2 a, b, normal;
  double cell = 0;
};

constexpr int kSamplesAlong = 24;
constexpr double kMinPixelsPerCell = 4;

std::optional<Side> side_of(const std::vector<Vec2>& q, std::size_t k, const Vec2& centre,
                            int border_cells) {
  Side s;
  s.a = q[k];
  s.b = q[(k + 1) % 4];
  const Vec2 d = s.b - s.a;
  if (!(d.norm() > 0)) return std::nullopt;
  s.normal = Vec2(d.y(), -d.x()).normalized();
  if (s.normal.dot(s.a - centre) < 0) s.normal = -s.normal;
  // The adjacent side, measured across this one, spans the square's width.
  const double across = std::abs((q[(k + 3) % 4] - s.a).dot(s.normal));
  s.cell = across / border_cells;
  // A profile across the side needs several samples per cell; sparse rings (a spinning LiDAR's
  // marker at 10 m: 2-3 rows per cell) put the crossing a whole ring off.
  if (!(s.cell >= kMinPixelsPerCell)) return std::nullopt;
  return s;
}

Vec2 point_on(const Side& s, double along, double out) {
  return s.a + along * (s.b - s.a) + out * s.cell * s.normal;
}

// Where a line through p with direction d meets the line through q with direction e.
std::optional<Vec2> meet(const Vec2& p, const Vec2& d, const Vec2& q, const Vec2& e) {
  const double det = d.x() * e.y() - d.y() * e.x();
  if (std::abs(det) < 1e-9) return std::nullopt;
  const Vec2 w = q - p;
  const double t = (w.x() * e.y() - w.y() * e.x()) / det;
  return p + t * d;
}

}  // namespace

EdgeRefinement refine_edges_to_mid_level(const std::vector<Vec2>& corners_px,
                                         const ProjectedImage& image, int border_cells) {
  EdgeRefinement result;
  result.corners_px = corners_px;
  if (corners_px.size() != 4 || border_cells < 2 || image.intensity.empty()) return result;
  Vec2 centre = Vec2::Zero();
  for (const Vec2& p : corners_px) {
    if (!p.allFinite()) return result;
    centre += p / 4;
  }
  std::vector<Side> sides;
  for (std::size_t k = 0; k < 4; ++k) {
    const std::optional<Side> s = side_of(corners_px, k, centre, border_cells);
    if (!s) return result;
    sides.push_back(*s);
  }

  // The levels: the middle of the black border (half a cell inside) and of the one-cell quiet zone
  // (0.6 cell outside: a detected side that sits inside the true edge would otherwise put the
  // white samples within the footprint's reach of the black), away from the corners.
  std::vector<double> black, white;
  for (const Side& s : sides) {
    for (int i = 0; i < kSamplesAlong; ++i) {
      const double along = 0.15 + 0.7 * i / (kSamplesAlong - 1);
      if (auto v = intensity_at(image, point_on(s, along, -0.5))) black.push_back(*v);
      if (auto v = intensity_at(image, point_on(s, along, 0.6))) white.push_back(*v);
    }
  }
  if (black.size() < 8 || white.size() < 8) return result;
  result.black = median(black);
  result.white = median(white);
  if (!(result.white - result.black > 0)) return result;
  const double mid = (result.black + result.white) / 2;

  // Each side: across it from the border's middle outwards, the first crossing of the mid level.
  constexpr int kStepsPerCell = 40;
  std::vector<double> shift(4);
  for (std::size_t k = 0; k < 4; ++k) {
    std::vector<double> crossings;
    for (int i = 0; i < kSamplesAlong; ++i) {
      const double along = 0.15 + 0.7 * i / (kSamplesAlong - 1);
      bool have_previous = false;
      double previous = 0;
      for (int j = -kStepsPerCell / 2; j <= kStepsPerCell / 2; ++j) {
        const double out = double(j) / kStepsPerCell;
        const std::optional<double> v = intensity_at(image, point_on(sides[k], along, out));
        if (!v) continue;  // a hole: the crossing is interpolated across it
        if (have_previous && previous < mid && *v >= mid) {
          const double step = 1.0 / kStepsPerCell;
          crossings.push_back(out - step + step * (mid - previous) / (*v - previous));
          break;
        }
        have_previous = true;
        previous = *v;
      }
    }
    if (crossings.size() < kSamplesAlong / 3) return result;
    shift[k] = std::clamp(median(crossings), -0.5, 0.5) * sides[k].cell;  // pixels, outwards
  }

  // Move each side along its normal; the corners are where adjacent sides meet.
  std::vector<Vec2> refined(4);
  for (std::size_t k = 0; k < 4; ++k) {
    const Side& s = sides[k];
    const Side& previous = sides[(k + 3) % 4];
    const std::optional<Vec2> corner =
        meet(s.a + shift[k] * s.normal, s.b - s.a,
             previous.a + shift[(k + 3) % 4] * previous.normal, previous.b - previous.a);
    if (!corner || (*corner - corners_px[k]).norm() > 2 * std::max(s.cell, previous.cell))
      return result;
    refined[k] = *corner;
  }
  result.corners_px = refined;
  result.mean_shift_px = (shift[0] + shift[1] + shift[2] + shift[3]) / 4;
  result.ok = true;
  return result;
}

}  // namespace iilfm
