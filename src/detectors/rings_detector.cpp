#include "rings_detector.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "iilfm/error.hpp"
#include "iilfm/rings_family.hpp"

namespace iilfm::detail {

namespace {

constexpr int kMinContourPoints = 8;
constexpr double kMaxAxisRatio = 4.0;  // a circle seen at up to about 75 degrees incidence
constexpr int kOutlinePoints = 16;

// An ellipse fitted to one contour: centre, semi-axes along its own axes, and how round the
// contour really was.
struct Ellipse {
  Vec2 centre;
  double a = 0, b = 0;  // semi-axes along `axis` and across it, pixels
  Vec2 axis;            // unit vector of the first axis
  double mean_radius() const { return std::sqrt(a * b); }
  double area() const { return a * b; }
  // The image point at radius `r` (1 = on the ellipse) and angle `t` of the unit circle, for
  // concentric circles whose common centre is imaged at `origin`: the centre of the image of the
  // circle of radius r lies r^2 of the way from there to this ellipse's centre (the perspective
  // bias grows with the square of the radius).
  Vec2 at(double r, double t, const Vec2& origin) const {
    const Vec2 across(-axis.y(), axis.x());
    return origin + r * r * (centre - origin) +
           r * (a * std::cos(t) * axis + b * std::sin(t) * across);
  }
  Vec2 at(double r, double t) const { return at(r, t, centre); }
  // The normalised radius of an image point (1 on the ellipse).
  double radius_of(const Vec2& p) const {
    const Vec2 d = p - centre;
    const double u = d.dot(axis) / a, v = (d.x() * -axis.y() + d.y() * axis.x()) / b;
    return std::hypot(u, v);
  }
};

// The ellipse of a contour, or nothing when the contour is too short, too flat or not elliptic
// (RMS distance from the fit over half a pixel plus 5 % of its radius).
std::optional<Ellipse> fit_contour(const std::vector<cv::Point>& contour) {
  if (contour.size() < kMinContourPoints) return std::nullopt;
  const cv::RotatedRect box = cv::fitEllipse(contour);
  Ellipse e;
  e.centre = Vec2(box.center.x, box.center.y);
  e.a = 0.5 * box.size.width;
  e.b = 0.5 * box.size.height;
  const double angle = box.angle * M_PI / 180.0;
  e.axis = Vec2(std::cos(angle), std::sin(angle));
  if (!(e.a > 1) || !(e.b > 1) || std::max(e.a, e.b) > kMaxAxisRatio * std::min(e.a, e.b))
    return std::nullopt;
  double sum_sq = 0;
  for (const cv::Point& p : contour) {
    const double off = (e.radius_of(Vec2(p.x, p.y)) - 1) * e.mean_radius();
    sum_sq += off * off;
  }
  if (std::sqrt(sum_sq / contour.size()) > 0.5 + 0.05 * e.mean_radius()) return std::nullopt;
  return e;
}

// Bilinear grey value at a sub-pixel position (pixel centres at integers); nothing outside.
std::optional<double> sample(const cv::Mat& gray, const Vec2& p) {
  const double x = p.x(), y = p.y();
  if (!(x >= 0 && y >= 0 && x <= gray.cols - 1 && y <= gray.rows - 1)) return std::nullopt;
  const int x0 = std::min(static_cast<int>(x), gray.cols - 2 < 0 ? 0 : gray.cols - 2);
  const int y0 = std::min(static_cast<int>(y), gray.rows - 2 < 0 ? 0 : gray.rows - 2);
  const int x1 = std::min(x0 + 1, gray.cols - 1), y1 = std::min(y0 + 1, gray.rows - 1);
  const double fx = x - x0, fy = y - y0;
  const auto v = [&](int c, int r) { return static_cast<double>(gray.at<std::uint8_t>(r, c)); };
  return (1 - fy) * ((1 - fx) * v(x0, y0) + fx * v(x1, y0)) +
         fy * ((1 - fx) * v(x0, y1) + fx * v(x1, y1));
}

// The grey values sampled around the middle half of a ring between radii r_in and r_out.
struct Ring {
  std::vector<double> values;
  double mean = 0;
};

std::optional<Ring> sample_ring(const cv::Mat& gray, const Ellipse& outer, const Vec2& origin,
                                double r_in, double r_out) {
  Ring ring;
  const double width = r_out - r_in;
  for (const double f : {0.3, 0.5, 0.7}) {
    const double r = r_in + f * width;
    const int n = std::max(8, static_cast<int>(std::ceil(2 * M_PI * r * outer.mean_radius())));
    for (int k = 0; k < n; ++k) {
      const std::optional<double> v = sample(gray, outer.at(r, 2 * M_PI * k / n, origin));
      if (!v) return std::nullopt;
      ring.values.push_back(*v);
    }
  }
  double sum = 0;
  for (double v : ring.values) sum += v;
  ring.mean = sum / ring.values.size();
  return ring;
}

double agreement(const Ring& ring, double mid, bool black) {
  std::size_t agree = 0;
  for (double v : ring.values) agree += (v < mid) == black;
  return static_cast<double>(agree) / ring.values.size();
}

int popcount(std::uint32_t v) {
  int n = 0;
  for (; v; v &= v - 1) ++n;
  return n;
}

class RingsDetector final : public MarkerDetector {
 public:
  RingsDetector(const RingsFamily& family, const RingsOptions& options)
      : family_(family), options_(options), name_("rings:" + family.name) {}

  const std::string& family() const override { return name_; }

  void detect(const cv::Mat& gray, std::vector<Detection>& out) override {
    CV_Assert(gray.type() == CV_8UC1);
    if (gray.cols < 8 || gray.rows < 8) return;
    // Dark pixels are the foreground; Otsu's level splits a binarised image at mid-grey too.
    cv::Mat dark;
    cv::threshold(gray, dark, 0, 255, cv::THRESH_BINARY_INV | cv::THRESH_OTSU);
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(dark, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
    std::vector<Ellipse> ellipses;
    for (const auto& contour : contours)
      if (const auto e = fit_contour(contour)) ellipses.push_back(*e);
    std::sort(ellipses.begin(), ellipses.end(),
              [](const Ellipse& x, const Ellipse& y) { return x.area() > y.area(); });

    std::vector<bool> used(ellipses.size(), false);
    std::vector<Ellipse> found;  // outer edges of the markers decoded so far
    const double min_radius = options_.min_ring_px * family_.annuli();
    for (std::size_t i = 0; i < ellipses.size(); ++i) {
      if (used[i] || std::min(ellipses[i].a, ellipses[i].b) < min_radius) continue;
      // The contour traces the outermost dark pixels, half a pixel inside the frame's edge.
      Ellipse outer = ellipses[i];
      outer.a += 0.5;
      outer.b += 0.5;
      // Another contour of a decoded marker (a ring's edge traced from the other side, a hole
      // of unobserved pixels on it) would report it twice.
      if (std::any_of(found.begin(), found.end(),
                      [&](const Ellipse& f) { return f.radius_of(outer.centre) < 1; }))
        continue;
      std::vector<std::size_t> inner = concentric_boundaries(ellipses, i, outer);
      if (inner.empty()) continue;  // not even the frame's inner edge: no ring marker
      const Vec2 origin = centre(ellipses, i, inner);
      Detection det;
      if (!decode(gray, outer, origin, det)) continue;
      used[i] = true;
      for (std::size_t j : inner) used[j] = true;
      found.push_back(outer);
      det.family = name_;
      det.corners_px = {origin};
      det.keypoints_marker = {Vec2(0, 0)};
      for (int k = 0; k < kOutlinePoints; ++k)
        det.outline_px.push_back(outer.at(1.0, 2 * M_PI * k / kOutlinePoints));
      out.push_back(std::move(det));
    }
  }

 private:
  // Smaller ellipses centred on `outer` whose size matches a ring boundary of the family.
  std::vector<std::size_t> concentric_boundaries(const std::vector<Ellipse>& ellipses,
                                                 std::size_t i, const Ellipse& outer) const {
    std::vector<std::size_t> inner;
    const double u = family_.ring_width();
    for (std::size_t j = i + 1; j < ellipses.size(); ++j) {
      const Ellipse& e = ellipses[j];
      // Perspective moves the outer ellipse's centre by up to about half a ring width (a 30 cm
      // marker 2 m away at 45 degrees); a full ring width leaves room for noise.
      if ((e.centre - outer.centre).norm() > u * outer.mean_radius()) continue;
      const double boundaries = (1 - e.mean_radius() / outer.mean_radius()) / u;
      if (boundaries < 0.5 || std::abs(boundaries - std::round(boundaries)) > 0.35) continue;
      inner.push_back(j);
    }
    return inner;
  }

  // Reads the rings inside `outer`: the frame and centre black, the guard and the paper outside
  // white, every ring clearly one or the other, and the data rings a code of the family.
  bool decode(const cv::Mat& gray, const Ellipse& outer, const Vec2& origin, Detection& det) const {
    const int n = family_.annuli();
    const double u = family_.ring_width();
    std::vector<Ring> rings;
    for (int k = 0; k < n; ++k) {
      const auto ring = sample_ring(gray, outer, origin, std::max(0.0, 1 - (k + 1) * u), 1 - k * u);
      if (!ring) return false;
      rings.push_back(*ring);
    }
    const auto paper =
        sample_ring(gray, outer, origin, 1 + 0.25 * kRingsQuietZone, 1 + kRingsQuietZone);
    if (!paper) return false;
    const double black = rings.front().mean, white = 0.5 * (rings[1].mean + paper->mean);
    if (white - black < options_.min_contrast * 255) return false;
    const double mid = 0.5 * (black + white);
    if (agreement(*paper, mid, false) < options_.min_ring_agreement) return false;
    std::uint32_t code = 0;
    double margin = 1;
    for (int k = 0; k < n; ++k) {
      const bool is_black = rings[k].mean < mid;
      const bool fixed = k < 2 || k == n - 1;
      if (fixed && is_black != family_.annulus_black(0, k)) return false;
      if (agreement(rings[k], mid, is_black) < options_.min_ring_agreement) return false;
      margin = std::min(margin, std::abs(rings[k].mean - mid) / (white - black) * 2);
      if (!fixed) code = (code << 1) | (is_black ? 1u : 0u);
    }
    int best = -1, best_distance = family_.bits + 1;
    for (std::size_t id = 0; id < family_.codes.size(); ++id) {
      const int d = popcount(family_.codes[id] ^ code);
      if (d < best_distance) {
        best_distance = d;
        best = static_cast<int>(id);
      }
    }
    if (best < 0 || best_distance > options_.max_hamming) return false;
    det.id = best;
    det.hamming = best_distance;
    det.decision_margin = margin;
    return true;
  }

  // The image of the marker's centre. Under perspective the centre of a circle's image ellipse
  // lies off the image of the circle's centre by an amount that grows with the square of the
  // radius, along one line for concentric circles: the ellipse centres regressed on the squared
  // radius, taken at radius zero, remove that first-order bias. Without boundaries far enough
  // apart to regress on, the smallest ellipse's centre (the least biased) stands.
  static Vec2 centre(const std::vector<Ellipse>& ellipses, std::size_t outer,
                     const std::vector<std::size_t>& inner) {
    std::vector<std::size_t> group = inner;
    group.push_back(outer);
    double s_min = 1e300, s_max = 0, mean_s = 0;
    Vec2 mean_c(0, 0);
    for (std::size_t j : group) {
      const double s = ellipses[j].area();
      s_min = std::min(s_min, s);
      s_max = std::max(s_max, s);
      mean_s += s / group.size();
      mean_c += ellipses[j].centre / static_cast<double>(group.size());
    }
    const Ellipse& smallest = ellipses[inner.back()];  // sorted by falling area
    if (group.size() < 3 || s_min > 0.25 * s_max) return smallest.centre;
    double var = 0;
    Vec2 cov(0, 0);
    for (std::size_t j : group) {
      const double ds = ellipses[j].area() - mean_s;
      var += ds * ds;
      cov += ds * (ellipses[j].centre - mean_c);
    }
    return mean_c - (cov / var) * mean_s;
  }

  const RingsFamily& family_;
  RingsOptions options_;
  std::string name_;
};

}  // namespace

std::unique_ptr<MarkerDetector> make_rings_detector(const std::string& family,
                                                    const RingsOptions& options) {
  if (options.max_hamming < 0 || options.max_hamming > 1)
    throw InputError("rings: max Hamming must be 0 or 1 (the codes are 3 apart)");
  return std::make_unique<RingsDetector>(find_rings_family(family), options);
}

std::vector<std::string> rings_families_names() {
  std::vector<std::string> names;
  for (const RingsFamily& f : rings_families()) names.push_back(f.name);
  return names;
}

FamilyLayout rings_layout(const std::string& family) {
  const RingsFamily& f = find_rings_family(family);
  const int across = 2 * f.annuli();
  const int quiet = static_cast<int>(std::lround(kRingsQuietZone * f.annuli()));
  return {across, across + 2 * quiet, f.min_distance, static_cast<int>(f.codes.size())};
}

}  // namespace iilfm::detail
