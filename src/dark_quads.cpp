#include "dark_quads.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <utility>

#include "banded_contours.hpp"

namespace iilfm::detail {

namespace {

struct DarkBlob {
  const std::vector<cv::Point>* contour;
  cv::Rect box;
  double area;                  // enclosed by the outline through the pixel centres
  std::vector<cv::Point> hull;  // empty until a pair needs it

  // Its pixels, by Pick's theorem from the outline through their centres: the area counts none
  // of a one-pixel-wide part (a far square's border column between two rings' gaps).
  double pixels() const { return area + 0.5 * static_cast<double>(contour->size()) + 1; }
};

const std::vector<cv::Point>& hull_of(DarkBlob& blob) {
  if (blob.hull.empty()) cv::convexHull(*blob.contour, blob.hull);
  return blob.hull;
}

// How far a small square's hull may stray from its quadrilateral (pixels): a corner cut by two
// pixels on either side.
constexpr double kMostCornerCutPx = 2.0;

// Of a pair's box, the least share its dark pixels may cover.
constexpr double kMinDarkShareOfBox = 0.2;

// A hull that approxPolyDP leaves with up to this many vertices may still be a square with a
// speck joined to one side or a corner cut: four of its vertices are tried (squarest_four).
constexpr std::size_t kMostHullVertices = 7;
// Of the hull, the least share those four must span, and the most their opposite sides may turn
// from parallel (sine of the angle: about 20 degrees).
constexpr double kMinShareOfHull = 0.75;
constexpr double kMostSideTurn = 0.35;
// The most a fitted side may turn from its opposite one (sine: about 8 degrees).
constexpr double kMostFittedTurn = 0.14;

// Sine of the angle between directions a and b.
double sine_between(const cv::Point2d& a, const cv::Point2d& b) {
  const double lengths = std::hypot(a.x, a.y) * std::hypot(b.x, b.y);
  return lengths > 0 ? std::abs(a.cross(b)) / lengths : 1.0;
}

// Of `poly`'s vertices (a hull's, in order), the four spanning the most area whose opposite sides
// are near parallel and which span most of `hull_area`. A dark speck of the wall joined to a
// border row (OS1-128, 1 m tag at 23 m: a ring that grazed the top edge, and the wall above it)
// adds a vertex that is not a corner; the square's own corners are the four that keep it square.
std::optional<std::vector<cv::Point>> squarest_four(const std::vector<cv::Point>& poly,
                                                    double hull_area) {
  const std::size_t n = poly.size();
  std::optional<std::vector<cv::Point>> best;
  double best_area = kMinShareOfHull * hull_area;
  std::vector<cv::Point> q;
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b)
      for (std::size_t c = b + 1; c < n; ++c)
        for (std::size_t d = c + 1; d < n; ++d) {
          q = {poly[a], poly[b], poly[c], poly[d]};
          const double area = cv::contourArea(q);
          if (area <= best_area || sine_between(q[1] - q[0], q[2] - q[3]) > kMostSideTurn ||
              sine_between(q[2] - q[1], q[3] - q[0]) > kMostSideTurn)
            continue;
          best_area = area;
          best = q;
        }
  return best;
}

// The least box a square may have: as wide as its sides, and as tall or a little less.
struct LeastBox {
  double width, height;
};

// Whether an outline of `points` points in a box `box` is long and large enough for a square of
// at least `least`, and small enough to be a marker in `image`: the cheap tests, made before the
// hull.
bool may_hold_square(std::size_t points, const cv::Rect& box, const LeastBox& least,
                     const cv::Size& image) {
  return static_cast<double>(points) >= 2 * (least.width + least.height) &&
         box.width >= least.width && box.height >= least.height && box.width <= image.width / 4 &&
         box.height <= image.height * 3 / 4;
}

// Dark pixels of `dark` (a band of the image starting at `origin`) inside the convex `hull`
// (image coordinates), and the pixels inside it.
std::pair<int, int> dark_pixels_in_hull(const cv::Mat& dark, cv::Point origin,
                                        const std::vector<cv::Point>& hull) {
  const cv::Rect box = cv::boundingRect(hull) & cv::Rect(origin, dark.size());
  if (box.empty()) return {0, 0};
  thread_local cv::Mat inside, both;
  inside.create(box.size(), CV_8U);
  inside.setTo(0);
  thread_local std::vector<cv::Point> shifted;
  shifted.clear();
  for (const cv::Point& p : hull) shifted.push_back(p - box.tl());
  cv::fillConvexPoly(inside, shifted, 255);
  cv::bitwise_and(dark(box - origin), inside, both);
  return {cv::countNonZero(both), cv::countNonZero(inside)};
}

// The corners where the sides `lines` (direction, point; in order around the square) meet,
// clockwise on the screen (y down), the corner order of square markers; none when two neighbours
// are parallel.
std::optional<std::array<Vec2, 4>> corners_of(const std::array<cv::Vec4f, 4>& lines) {
  std::array<Vec2, 4> quad;
  for (int k = 0; k < 4; ++k) {
    // Corner k + 1 is where side k meets side k + 1.
    const cv::Vec4f& l1 = lines[k];
    const cv::Vec4f& l2 = lines[(k + 1) % 4];
    const double det = l1[0] * -l2[1] - l1[1] * -l2[0];
    if (std::abs(det) < 1e-6) return std::nullopt;
    const double dx = l2[2] - l1[2], dy = l2[3] - l1[3];
    const double t = (dx * -l2[1] - dy * -l2[0]) / det;
    quad[(k + 1) % 4] = Vec2(l1[2] + t * l1[0], l1[3] + t * l1[1]);
  }
  const double turn = (quad[1] - quad[0]).x() * (quad[2] - quad[1]).y() -
                      (quad[1] - quad[0]).y() * (quad[2] - quad[1]).x();
  if (turn < 0) std::swap(quad[1], quad[3]);
  return quad;
}

// Signed distance of `p` from the line `l` (direction, point).
float offset_from(const cv::Vec4f& l, const cv::Point2f& p) {
  return (p.x - l[2]) * l[1] - (p.y - l[3]) * l[0];
}

// Appends to `quads` the quadrilateral of a dark outline that may_hold_square: the points of
// `outlines` (one blob's contour, or two blobs'), whose convex hull is `hull` and whose contours
// enclose `enclosed` pixels, in `dark` (the dark pixels of the band from `origin`). Where two
// opposite fitted sides turn from parallel, the quad with the worse fitted one laid parallel to
// its opposite follows it.
void quad_of_outline(std::initializer_list<const std::vector<cv::Point>*> outlines,
                     const std::vector<cv::Point>& hull, double enclosed, const cv::Mat& dark,
                     cv::Point origin, std::vector<std::array<Vec2, 4>>& quads) {
  // The hull: data cells next to a border row no ring crossed notch the blob, not its hull.
  std::vector<cv::Point> poly;
  const double tolerance = 0.04 * cv::arcLength(hull, true);
  cv::approxPolyDP(hull, poly, tolerance, true);
  // A square ten pixels across (a 1 m tag at 16 m on an OS1-64) has its corners cut by a pixel or
  // two where a ring grazed them, more than that share of its outline: its hull is tried again
  // with that cut allowed.
  if (poly.size() != 4 && tolerance < kMostCornerCutPx)
    cv::approxPolyDP(hull, poly, kMostCornerCutPx, true);
  const double hull_area = cv::contourArea(hull);
  // Where four of the vertices were taken, the speck or cut left out is not counted below.
  bool four_taken = false;
  if (poly.size() > 4 && poly.size() <= kMostHullVertices) {
    if (auto four = squarest_four(poly, hull_area)) {
      poly = std::move(*four);
      four_taken = true;
    }
  }
  if (poly.size() != 4 || !cv::isContourConvex(poly)) return;
  if (hull_area < 0.9 * cv::contourArea(poly)) return;
  // Half the hull must be dark. A closed outline encloses its white data cells too; one open to
  // a side (a border row no ring crossed, and a white data cell next to it: an OS1-64's 40 cm tag
  // at 5-6 m) encloses little more than its own pixels, so those are counted.
  if (enclosed < 0.5 * hull_area) {
    const auto [dark_inside, inside] = dark_pixels_in_hull(dark, origin, four_taken ? poly : hull);
    if (dark_inside < 0.5 * inside) return;
  }
  // Per side, the outermost outline point at each step along it, between its vertices (ends
  // trimmed: staircase corners), and of those the ones within a pixel and a half of the side's
  // outer envelope (the upper quartile of the steps): white data cells next to a border row no
  // ring crossed notch the outline, and their points would pull the side inwards.
  constexpr float kEnvelopeDepth = 1.5f;
  cv::Point2f centre(0, 0);
  for (const cv::Point& p : poly) centre += cv::Point2f(p) * 0.25f;
  std::array<cv::Vec4f, 4> lines;
  std::array<std::vector<cv::Point2f>, 4> kept_points;  // empty for a hull's edge
  std::vector<cv::Point2f> side;
  std::vector<float> outermost, found;
  for (int k = 0; k < 4; ++k) {
    const cv::Point2f a = poly[k], b = poly[(k + 1) % 4];
    const cv::Point2f dir = b - a;
    const float len = static_cast<float>(cv::norm(dir));
    // Distance outwards from the side: positive on the side away from the centre.
    const float outwards = (centre - a).cross(dir) > 0 ? -1.0f : 1.0f;
    const int steps = static_cast<int>(len) + 1;
    side.assign(static_cast<std::size_t>(steps), cv::Point2f(0, 0));
    outermost.assign(static_cast<std::size_t>(steps), -1e9f);
    for (const std::vector<cv::Point>* outline : outlines) {
      for (const cv::Point& p : *outline) {
        const cv::Point2f d = cv::Point2f(p) - a;
        const float along = (d.x * dir.x + d.y * dir.y) / len;
        const float out = outwards * d.cross(dir) / len;
        if (!(along > 0.15f * len && along < 0.85f * len && std::abs(out) < 0.1f * len + 1.5f))
          continue;
        const auto step = static_cast<std::size_t>(along);
        if (out > outermost[step]) {
          outermost[step] = out;
          side[step] = cv::Point2f(p);
        }
      }
    }
    found.clear();
    for (float out : outermost)
      if (out > -1e9f) found.push_back(out);
    std::size_t kept = 0;
    if (found.size() >= 3) {
      const auto upper_quartile = found.begin() + static_cast<std::ptrdiff_t>(found.size() * 3 / 4);
      std::nth_element(found.begin(), upper_quartile, found.end());
      const float deepest = *upper_quartile - kEnvelopeDepth;
      for (std::size_t i = 0; i < side.size(); ++i)
        if (outermost[i] > -1e9f && outermost[i] >= deepest) side[kept++] = side[i];
    }
    side.resize(kept);
    if (side.size() >= 3) {
      cv::fitLine(side, lines[k], cv::DIST_L2, 0, 0.01, 0.01);
      kept_points[k] = side;
    } else {
      // Too few outline points along the side to fit (a border row no ring crossed, with white
      // data cells under it): the hull's edge. Ring decoding searches where the top and bottom
      // sides lie.
      lines[k] = cv::Vec4f(dir.x / len, dir.y / len, a.x, a.y);
    }
  }
  const std::optional<std::array<Vec2, 4>> fitted = corners_of(lines);
  if (!fitted) return;
  quads.push_back(*fitted);
  // Opposite sides of a square are near parallel unless it is seen close and obliquely. A ring
  // grazing a border row reads part of it black, part white, and the side fitted there can turn
  // by more (an OS1-128's 1 m tag at 20 m: 18 degrees). Such a square is also tried with the
  // worse fitted of the two (the larger spread of its points) laid parallel to its opposite,
  // through the median of its points: a second quad, as a blob's nested outlines give, read
  // apart and kept once per id.
  // RMS distance of side k's kept points from its line (0 for a hull's edge).
  const auto spread = [&](int k) {
    double squares = 0;
    for (const cv::Point2f& p : kept_points[k]) {
      const float off = offset_from(lines[k], p);
      squares += off * off;
    }
    const auto n = static_cast<double>(kept_points[k].size());
    return n > 0 ? static_cast<float>(std::sqrt(squares / n)) : 0.0f;
  };
  const auto direction = [](const cv::Vec4f& l) { return cv::Point2d(l[0], l[1]); };
  std::array<cv::Vec4f, 4> parallel = lines;
  bool relaid = false;
  for (int k = 0; k < 2; ++k) {
    if (sine_between(direction(lines[k]), direction(lines[k + 2])) <= kMostFittedTurn) continue;
    const int worse = spread(k) >= spread(k + 2) ? k : k + 2;
    if (kept_points[worse].empty()) continue;
    const cv::Vec4f& other = lines[worse == k ? k + 2 : k];
    std::vector<float> offsets;
    for (const cv::Point2f& p : kept_points[worse]) offsets.push_back(offset_from(other, p));
    const auto middle = offsets.begin() + static_cast<std::ptrdiff_t>(offsets.size() / 2);
    std::nth_element(offsets.begin(), middle, offsets.end());
    parallel[worse] =
        cv::Vec4f(other[0], other[1], other[2] + *middle * other[1], other[3] - *middle * other[0]);
    relaid = true;
  }
  if (!relaid) return;
  if (const std::optional<std::array<Vec2, 4>> quad = corners_of(parallel)) quads.push_back(*quad);
}

// Pixels shared by the ranges [a0, a1) and [b0, b1); negative: minus the gap between them.
int overlap_of(int a0, int a1, int b0, int b1) { return std::min(a1, b1) - std::max(a0, b0); }

}  // namespace

std::vector<std::array<Vec2, 4>> dark_quads(const cv::Mat& binary, double min_side_px, int cells,
                                            std::optional<double> min_height_px) {
  const LeastBox least{min_side_px, min_height_px.value_or(min_side_px)};
  // Traced on the rows where `binary` changes (banded_contours.hpp), thresholded there only:
  // uniform rows are uniform in `dark` too. The blobs spanning the width that this leaves out
  // would fail the box test anyway.
  const cv::Rect band = changing_band(binary);
  if (band.empty()) return {};
  thread_local cv::Mat dark;
  cv::compare(binary(band), 128, dark, cv::CMP_LT);
  std::vector<std::vector<cv::Point>> contours;
  contours_in_band(dark, band, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, contours);
  const cv::Size image = binary.size();
  std::vector<std::array<Vec2, 4>> quads;
  std::vector<DarkBlob> parts;  // blobs that may be part of a square cut in two
  for (const std::vector<cv::Point>& contour : contours) {
    const cv::Rect box = cv::boundingRect(contour);
    // Specks and blobs too large for a square are neither a square nor part of one.
    if (box.width < 2 || box.height < 2 || box.width > image.width / 4 ||
        box.height > image.height * 3 / 4)
      continue;
    DarkBlob blob{&contour, box, cv::contourArea(contour), {}};
    if (may_hold_square(contour.size(), box, least, image)) {
      quad_of_outline({&contour}, hull_of(blob), blob.area, dark, band.tl(), quads);
    }
    parts.push_back(std::move(blob));
  }
  if (cells <= 0) return quads;
  // Pairs of parts at most half a cell apart (a marker's white margin is a cell), found along x in
  // order of their boxes' left sides; widest_gap bounds that half cell for a box within the test's.
  std::sort(parts.begin(), parts.end(),
            [](const DarkBlob& a, const DarkBlob& b) { return a.box.x < b.box.x; });
  const int widest_gap = image.width / 4 / cells + 1;
  std::vector<cv::Point> hulls, hull;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    DarkBlob& a = parts[i];
    for (std::size_t j = i + 1; j < parts.size(); ++j) {
      DarkBlob& b = parts[j];
      if (b.box.x > a.box.x + a.box.width + widest_gap) break;
      const cv::Rect both = a.box | b.box;
      const int overlap_x =
          overlap_of(a.box.x, a.box.x + a.box.width, b.box.x, b.box.x + b.box.width);
      const int overlap_y =
          overlap_of(a.box.y, a.box.y + a.box.height, b.box.y, b.box.y + b.box.height);
      const int widest = std::min(both.width, both.height) / (2 * cells) + 1;
      if (-overlap_x > widest || -overlap_y > widest) continue;
      // The dark area must fill half the hull, and a quad's hull a good part of its box (half for
      // a square turned 45 degrees): a cheap test before the hull.
      if (!may_hold_square(a.contour->size() + b.contour->size(), both, least, image) ||
          a.pixels() + b.pixels() < kMinDarkShareOfBox * both.area())
        continue;
      // The hull of the two parts' hulls is the hull of their outlines.
      const std::vector<cv::Point>& hull_a = hull_of(a);
      const std::vector<cv::Point>& hull_b = hull_of(b);
      hulls.assign(hull_a.begin(), hull_a.end());
      hulls.insert(hulls.end(), hull_b.begin(), hull_b.end());
      cv::convexHull(hulls, hull);
      quad_of_outline({a.contour, b.contour}, hull, a.area + b.area, dark, band.tl(), quads);
    }
  }
  return quads;
}

}  // namespace iilfm::detail
