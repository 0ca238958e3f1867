#include "search_regions.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "../banded_contours.hpp"
#include "../cpu_clones.hpp"

namespace iilfm::detail {

namespace {

// libapriltag thresholds in 4 x 4 tiles, each against the extremes of its 3 x 3 tile
// neighbourhood. A box starting on a tile and reaching two tiles past a boundary (the default
// margin) sees, around that boundary, the tiles and thresholds of the whole image.
constexpr int kTile = 4;
// Beyond this many candidate boundaries (a noisy image) merging boxes costs more than it saves.
constexpr std::size_t kMostCandidates = 512;

int floor_to_tile(int v) { return v / kTile * kTile; }

// The box around a boundary widened by `margin`, clipped to the image and aligned to tiles (its
// far sides at a tile's end or at the image's edge, so partial tiles are the image's own).
cv::Rect widened(const cv::Rect& box, int margin, const cv::Size& size) {
  const int x0 = floor_to_tile(std::max(0, box.x - margin));
  const int y0 = floor_to_tile(std::max(0, box.y - margin));
  const int x1 = std::min(size.width, floor_to_tile(box.br().x + margin + kTile - 1));
  const int y1 = std::min(size.height, floor_to_tile(box.br().y + margin + kTile - 1));
  return {x0, y0, x1 - x0, y1 - y0};
}

// Could this boundary be a marker's border? Its box spans the smallest quad, is not a sliver, does
// not touch the image edge, and the boundary simplifies to a few corners (a smooth skyline or a
// staircase of ring steps does not). A ragged one passes when its convex hull simplifies to at
// most five corners and the boundary encloses at least half of the hull: a far marker on a Livox
// image, its border notched by holes and blurred cells, simplified to 15-20 corners and was never
// searched (Mid-40, 30 cm tag36h11 at 10 m: found in 4 of 10 scans, 10 with the hull), while a
// ragged floor edge or skyline still fails (touching the edge, or a sliver, or not filling its
// hull).
bool could_be_quad(const std::vector<cv::Point>& contour, const cv::Rect& box, const cv::Size& size,
                   const SearchRegionRules& rules, std::vector<cv::Point>& polygon) {
  if (box.x == 0 || box.y == 0 || box.br().x == size.width || box.br().y == size.height)
    return false;
  const int longer = std::max(box.width, box.height), shorter = std::min(box.width, box.height);
  if (longer < rules.min_side_px || longer > rules.max_aspect * shorter) return false;
  const double tolerance = std::clamp(0.02 * cv::arcLength(contour, true), 2.0, 5.0);
  cv::approxPolyDP(contour, polygon, tolerance, true);
  if (static_cast<int>(polygon.size()) <= rules.max_vertices) return true;
  thread_local std::vector<cv::Point> hull;
  cv::convexHull(contour, hull);
  cv::approxPolyDP(hull, polygon, tolerance, true);
  return static_cast<int>(polygon.size()) <= rules.max_hull_vertices &&
         cv::contourArea(contour) >= rules.min_hull_fill * cv::contourArea(hull);
}

// Unites overlapping regions until all are disjoint, so every boundary lies whole in one.
void merge_overlapping(std::vector<SearchRegion>& regions) {
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < regions.size(); ++i) {
      for (std::size_t j = i + 1; j < regions.size();) {
        if ((regions[i].box & regions[j].box).area() > 0) {
          regions[i].box |= regions[j].box;
          regions[i].least_outer_side_px =
              std::min(regions[i].least_outer_side_px, regions[j].least_outer_side_px);
          regions[j] = regions.back();
          regions.pop_back();
          merged = true;
        } else {
          ++j;
        }
      }
    }
  }
}

// Black-white changes between neighbours along the rows. Counted in byte lanes over runs of 224
// pixels (a count below 256, seven vectors of 32), so the vector loop compares and adds 32
// pixels at a time with no remainder inside a row (an int counter widened every byte to four
// lanes of 32 bits).
IILFM_AVX2_CLONES std::size_t row_changes(const cv::Mat& binary) {
  constexpr int kMostPerRun = 224;
  std::size_t changes = 0;
  for (int r = 0; r < binary.rows; ++r) {
    const std::uint8_t* __restrict row = binary.ptr<std::uint8_t>(r);
    for (int begin = 1; begin < binary.cols; begin += kMostPerRun) {
      const int end = std::min(binary.cols, begin + kMostPerRun);
      std::uint8_t in_run = 0;
      for (int c = begin; c < end; ++c) in_run += row[c] != row[c - 1] ? 1 : 0;
      changes += in_run;
    }
  }
  return changes;
}

}  // namespace

IILFM_AVX2_CLONES bool is_binary(const cv::Mat& image) {
  CV_Assert(image.type() == CV_8UC1);
  for (int r = 0; r < image.rows; ++r) {
    const std::uint8_t* row = image.ptr<std::uint8_t>(r);
    // v + 1 wraps 255 to 0, so (v + 1) & 0xFE is zero exactly for 0 and 255.
    std::uint8_t other = 0;
    for (int c = 0; c < image.cols; ++c) other |= static_cast<std::uint8_t>(row[c] + 1) & 0xFE;
    if (other) return false;
  }
  return true;
}

std::vector<SearchRegion> sized_search_regions(const cv::Mat& binary,
                                               const SearchRegionRules& rules) {
  const cv::Size size = binary.size();
  const std::vector<SearchRegion> whole{{cv::Rect(cv::Point(0, 0), size), 0}};
  const int crossing = rules.crossing_column;
  if (crossing < 0 && static_cast<double>(row_changes(binary)) >
                          rules.max_change_density * static_cast<double>(size.area()))
    return whole;
  thread_local std::vector<std::vector<cv::Point>> contours;
  thread_local std::vector<cv::Point> polygon;
  thread_local std::vector<cv::Rect> outlines;
  // Those spanning the width touch the image's edges: could_be_quad drops them anyway.
  contours_narrower_than_image(binary, cv::RETR_LIST, cv::CHAIN_APPROX_SIMPLE, contours);
  std::vector<SearchRegion> regions;
  outlines.clear();
  for (const std::vector<cv::Point>& contour : contours) {
    const cv::Rect box = cv::boundingRect(contour);
    const int longer = std::max(box.width, box.height);
    const int margin = rules.margin_px + static_cast<int>(std::ceil(rules.reach * longer));
    const cv::Rect region = widened(box, margin, size);
    if (crossing >= 0 && (region.x > crossing || region.br().x <= crossing)) continue;
    if (!could_be_quad(contour, box, size, rules, polygon)) continue;
    if (regions.size() == kMostCandidates) return whole;
    // A turned square's box is up to 1.41 times its side: the side is the rotated box's.
    const cv::Size2f turned = cv::minAreaRect(contour).size;
    regions.push_back({region, static_cast<int>(std::min(turned.width, turned.height))});
    outlines.push_back(box);
  }
  // A candidate inside another's box (a cell inside a marker's border, the border's own inner
  // outline) does not set its region's least side.
  for (std::size_t i = 0; i < outlines.size(); ++i)
    for (std::size_t j = 0; j < outlines.size(); ++j)
      if (j != i && outlines[i] != outlines[j] && (outlines[i] & outlines[j]) == outlines[i]) {
        regions[i].least_outer_side_px = std::numeric_limits<int>::max();
        break;
      }
  merge_overlapping(regions);
  double area = 0;
  int least = std::numeric_limits<int>::max();
  for (const SearchRegion& region : regions) {
    area += region.box.area();
    least = std::min(least, region.least_outer_side_px);
  }
  // Searched whole because the regions would cover most of it (a dense grid of close markers),
  // the image's outlines are still known.
  if (area > rules.max_coverage * static_cast<double>(size.area()))
    return {{whole.front().box, regions.empty() ? 0 : least}};
  return regions;
}

std::vector<cv::Rect> search_regions(const cv::Mat& binary, const SearchRegionRules& rules) {
  std::vector<cv::Rect> boxes;
  for (const SearchRegion& region : sized_search_regions(binary, rules))
    boxes.push_back(region.box);
  return boxes;
}

}  // namespace iilfm::detail
