#include "aruco_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/aruco.hpp>
#include <opencv2/imgproc.hpp>

#include "aruco_dictionaries.hpp"
#include "iilfm/error.hpp"
#include "search_regions.hpp"

namespace iilfm::detail {

namespace {

int opencv_refine_method(ArucoRefine refine) {
  switch (refine) {
    case ArucoRefine::kNone:
      return cv::aruco::CORNER_REFINE_NONE;
    case ArucoRefine::kSubpixel:
      return cv::aruco::CORNER_REFINE_SUBPIX;
    case ArucoRefine::kContour:
      return cv::aruco::CORNER_REFINE_CONTOUR;
    case ArucoRefine::kAprilTag:
      return cv::aruco::CORNER_REFINE_APRILTAG;
  }
  return cv::aruco::CORNER_REFINE_NONE;
}

class ArucoDetector final : public MarkerDetector {
 public:
  ArucoDetector(const ArucoDictionaryEntry& entry, const ArucoOptions& options)
      : name_(std::string("aruco:") + entry.name),
        dictionary_(cv::aruco::getPredefinedDictionary(entry.id)),
        parameters_(aruco_parameters(options)),
        options_(options),
        border_width_(dictionary_->markerSize + 2) {
    // Around a boundary: half the largest adaptive-threshold window and OpenCV's 3-pixel border
    // rule; a cell beyond the border, doubled for perspective (docs/detectors.md).
    rules_.margin_px = options.window_max / 2 + 4;
    rules_.reach = 2.0 / border_width_;
    rules_.min_side_px = border_width_ - 1;
  }

  const std::string& family() const override { return name_; }

  void detect(const cv::Mat& gray, std::vector<Detection>& out) override {
    detect_with(gray, rules_, out);
  }

  void detect_images(const DetectorImages& images, std::vector<Detection>& out) override {
    SearchRegionRules rules = rules_;
    rules.crossing_column = images.crossing_column;
    detect_with(images.image, rules, out);
  }

 private:
  void detect_with(const cv::Mat& gray, const SearchRegionRules& rules,
                   std::vector<Detection>& out) {
    CV_Assert(gray.type() == CV_8UC1);
    detect_in_search_regions(
        gray, options_.search_regions, rules, crop_,
        [&](const cv::Mat& part, cv::Point origin, int /*least_outer_side_px*/) {
          detect_in(gray, part, origin, out);
        });
  }

  // Detects in `part` of `gray`, whose pixel (0, 0) is `origin` of `gray`.
  void detect_in(const cv::Mat& gray, const cv::Mat& part, cv::Point origin,
                 std::vector<Detection>& out) {
    // OpenCV's perimeter limits are rates of the image's larger side: scaled so that a part keeps
    // the whole image's limits in pixels.
    const double scale =
        static_cast<double>(std::max(gray.cols, gray.rows)) / std::max({part.cols, part.rows, 1});
    parameters_->minMarkerPerimeterRate = options_.min_perimeter_rate * scale;
    parameters_->maxMarkerPerimeterRate = options_.max_perimeter_rate * scale;
    corners_.clear();
    ids_.clear();
    cv::aruco::detectMarkers(part, dictionary_, corners_, ids_, parameters_);
    for (std::size_t i = 0; i < ids_.size(); ++i) {
      Detection det;
      det.family = name_;
      det.id = ids_[i];
      // OpenCV gives the corners clockwise from the top-left of the marker as drawMarker draws
      // it: already iilfm's order (tested).
      for (const cv::Point2f& c : corners_[i])
        det.corners_px.emplace_back(c.x + origin.x, c.y + origin.y);
      to_edge_convention(options_.refine, det.corners_px);
      if (plausible_marker_quad(det.corners_px, border_width_, options_) &&
          quiet_zone_fraction(gray, det.corners_px, border_width_) >= options_.min_quiet_zone)
        out.push_back(std::move(det));
    }
  }

  std::string name_;
  cv::Ptr<cv::aruco::Dictionary> dictionary_;
  cv::Ptr<cv::aruco::DetectorParameters> parameters_;
  ArucoOptions options_;
  int border_width_;
  std::vector<std::vector<cv::Point2f>> corners_;
  std::vector<int> ids_;
  SearchRegionRules rules_;
  cv::Mat crop_;  // a search region's pixels, reused from call to call
};

const ArucoDictionaryEntry& dictionary_or_throw(const std::string& dictionary) {
  const ArucoDictionaryEntry* entry = find_aruco_dictionary(dictionary);
  if (entry) return *entry;
  std::string names;
  for (const ArucoDictionaryEntry& e : aruco_dictionaries())
    names += (names.empty() ? "" : ", ") + std::string(e.name);
  throw InputError("unknown ArUco dictionary 'aruco:" + dictionary + "' (OpenCV predefines " +
                   names + ")");
}

}  // namespace

void check_aruco_options(const ArucoOptions& o) {
  if (o.window_min < 3 || o.window_max < o.window_min || o.window_step < 1)
    throw InputError("ArUco threshold windows need 3 <= min <= max and step >= 1");
  if (o.refine_window < 1) throw InputError("ArUco refinement window must be at least 1 pixel");
  if (!(o.min_perimeter_rate > 0) || !(o.max_perimeter_rate > o.min_perimeter_rate))
    throw InputError("ArUco perimeter rates need 0 < min < max");
  if (!(o.error_correction_rate >= 0 && o.error_correction_rate <= 1))
    throw InputError("ArUco error correction rate must lie in [0, 1]");
  if (!(o.min_cell_px >= 0) || !(o.max_side_ratio >= 1) ||
      !(o.min_quiet_zone >= 0 && o.min_quiet_zone <= 1))
    throw InputError(
        "ArUco filter needs min_cell_px >= 0, max_side_ratio >= 1, min_quiet_zone in [0, 1]");
}

cv::Ptr<cv::aruco::DetectorParameters> aruco_parameters(const ArucoOptions& o) {
  auto p = cv::aruco::DetectorParameters::create();
  p->adaptiveThreshWinSizeMin = o.window_min;
  p->adaptiveThreshWinSizeMax = o.window_max;
  p->adaptiveThreshWinSizeStep = o.window_step;
  p->adaptiveThreshConstant = o.threshold_constant;
  p->cornerRefinementMethod = opencv_refine_method(o.refine);
  p->cornerRefinementWinSize = o.refine_window;
  p->minMarkerPerimeterRate = o.min_perimeter_rate;
  p->maxMarkerPerimeterRate = o.max_perimeter_rate;
  p->errorCorrectionRate = o.error_correction_rate;
  return p;
}

// Measured (test_aruco_detector.cpp): the AprilTag refinement reports pixel centres at i + 0.5;
// the contour-based methods (none, contour) put the quad through the centres of the outermost
// black pixels, inside the true edge. Both are moved onto the edge, with centres at integers.
void to_edge_convention(ArucoRefine refine, std::vector<Vec2>& corners) {
  if (refine == ArucoRefine::kAprilTag) {
    for (Vec2& c : corners) c -= Vec2(0.5, 0.5);
  } else if (refine != ArucoRefine::kSubpixel) {
    push_edges_outward(corners);
  }
}

void push_edges_outward(std::vector<Vec2>& corners) {
  const std::size_t n = corners.size();
  if (n < 3) return;
  // Signed area decides which side of each edge is outside.
  double area2 = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2& a = corners[k];
    const Vec2& b = corners[(k + 1) % n];
    area2 += a.x() * b.y() - a.y() * b.x();
  }
  const double side = area2 > 0 ? 1.0 : -1.0;
  std::vector<Vec2> normal(n);
  std::vector<double> shift(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 e = (corners[(k + 1) % n] - corners[k]).normalized();
    normal[k] = side * Vec2(e.y(), -e.x());
    // The outermost pixel centres of a binarised edge lie, on average, half a lattice row inside
    // it; rows of pixel centres along direction e are max(|e.x|, |e.y|) apart.
    shift[k] = 0.5 * std::max(std::abs(e.x()), std::abs(e.y()));
  }
  const std::vector<Vec2> old = corners;
  for (std::size_t k = 0; k < n; ++k) {
    // Corner k lies on edges k-1 and k: solve v.n_{k-1} = s_{k-1}, v.n_k = s_k.
    const Vec2& n1 = normal[(k + n - 1) % n];
    const Vec2& n2 = normal[k];
    const double det = n1.x() * n2.y() - n1.y() * n2.x();
    if (std::abs(det) < 1e-9) continue;
    const double s1 = shift[(k + n - 1) % n], s2 = shift[k];
    const Vec2 v((s1 * n2.y() - s2 * n1.y()) / det, (n1.x() * s2 - n2.x() * s1) / det);
    corners[k] = old[k] + v;
  }
}

bool plausible_marker_quad(const std::vector<Vec2>& corners, int border_width,
                           const ArucoOptions& options) {
  if (corners.size() != 4) return false;
  double shortest = 1e300, longest = 0;
  double turn_sign = 0;
  for (int k = 0; k < 4; ++k) {
    const Vec2 edge = corners[(k + 1) % 4] - corners[k];
    const Vec2 next = corners[(k + 2) % 4] - corners[(k + 1) % 4];
    shortest = std::min(shortest, edge.norm());
    longest = std::max(longest, edge.norm());
    // Every turn of a convex quad has the same sign.
    const double turn = edge.x() * next.y() - edge.y() * next.x();
    if (turn == 0 || turn * turn_sign < 0) return false;
    turn_sign = turn;
  }
  return shortest >= options.min_cell_px * border_width &&
         longest <= options.max_side_ratio * shortest;
}

double quiet_zone_fraction(const cv::Mat& gray, const std::vector<Vec2>& corners,
                           int border_width) {
  CV_Assert(gray.type() == CV_8UC1 && corners.size() == 4 && border_width > 0);
  // Cell coordinates: the black square spans [0, n] x [0, n]; its corners are the quad's.
  const float n = static_cast<float>(border_width);
  const std::vector<cv::Point2f> square = {{0, 0}, {n, 0}, {n, n}, {0, n}};
  std::vector<cv::Point2f> quad;
  for (const Vec2& c : corners)
    quad.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
  const cv::Matx33d H = cv::getPerspectiveTransform(square, quad);
  auto value_at_cell = [&](double cx, double cy) -> double {
    const cv::Vec3d p = H * cv::Vec3d(cx, cy, 1);
    const double x = p[0] / p[2], y = p[1] / p[2];
    const int ix = static_cast<int>(std::floor(x)), iy = static_cast<int>(std::floor(y));
    if (ix < 0 || iy < 0 || ix + 1 >= gray.cols || iy + 1 >= gray.rows) return -1;  // unknown
    const double fx = x - ix, fy = y - iy;
    auto at = [&](int r, int c) { return static_cast<double>(gray.at<std::uint8_t>(r, c)); };
    return (1 - fy) * ((1 - fx) * at(iy, ix) + fx * at(iy, ix + 1)) +
           fy * ((1 - fx) * at(iy + 1, ix) + fx * at(iy + 1, ix + 1));
  };
  // Half the gray range: a binarised image gives 0 or 255, a gray one a clear step.
  constexpr double kMinStep = 64;
  int bright = 0, total = 0;
  for (int j = 0; j < border_width; ++j) {
    const double t = j + 0.5;
    // (margin cell, border cell) along the top, right, bottom and left sides.
    const double pairs[4][4] = {
        {t, -0.5, t, 0.5}, {n + 0.5, t, n - 0.5, t}, {t, n + 0.5, t, n - 0.5}, {-0.5, t, 0.5, t}};
    for (const auto& p : pairs) {
      const double margin = value_at_cell(p[0], p[1]), border = value_at_cell(p[2], p[3]);
      ++total;
      if (margin >= 0 && border >= 0 && margin - border >= kMinStep) ++bright;
    }
  }
  return static_cast<double>(bright) / total;
}

std::unique_ptr<MarkerDetector> make_aruco_detector(const std::string& dictionary,
                                                    const ArucoOptions& options) {
  const ArucoDictionaryEntry& entry = dictionary_or_throw(dictionary);
  check_aruco_options(options);
  return std::make_unique<ArucoDetector>(entry, options);
}

FamilyLayout aruco_layout(const std::string& dictionary) {
  const ArucoDictionaryEntry& entry = dictionary_or_throw(dictionary);
  const cv::Ptr<cv::aruco::Dictionary> dict = cv::aruco::getPredefinedDictionary(entry.id);
  const int bits = dict->markerSize;
  // OpenCV stores the correctable bits; its AprilTag dictionaries carry 0 there, so use their
  // families' published distances (16h5 ... 36h11).
  int distance = 2 * dict->maxCorrectionBits + 1;
  if (dictionary.rfind("DICT_APRILTAG_", 0) == 0) {
    const std::string family = dictionary.substr(14);
    distance = family == "16h5" ? 5 : family == "25h9" ? 9 : family == "36h10" ? 10 : 11;
  }
  return FamilyLayout{bits + 2, bits + 4, distance, dict->bytesList.rows};
}

}  // namespace iilfm::detail
