// Where in a binary image a square-marker detector can find a quad: the boxes around black-white
// boundaries shaped like a quadrilateral. libapriltag's cost grows with the pixels it is given
// (about 8 ns a pixel even where the image is uniform; OpenCV's ArUco is similar), so the AprilTag
// and ArUco back-ends run on these boxes instead of the whole image.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace iilfm::detail {

struct SearchRegionRules {
  // How far beyond a quad decoding reads, as a share of the quad's larger side (libapriltag
  // samples a white row half a cell outside the border, and some families keep data bits outside
  // it). Already doubled for perspective by the caller.
  double reach = 0.25;
  // Pixels added around a boundary besides the reach: the detector's own neighbourhoods (two of
  // libapriltag's threshold tiles; ArUco's adaptive threshold window).
  int margin_px = 8;
  int min_side_px = 8;     // a boundary must span this many pixels one way (the smallest quad)
  double max_aspect = 16;  // and be at most this much longer than wide
  int max_vertices = 12;   // its polygon, simplified to a few pixels, has at most this many
  // or, ragged, its convex hull simplifies to at most this many and it encloses at least this
  // share of the hull's area (6 let in the rosette holes' blobs of a single Mid-40 frame, whose
  // hulls simplify to 6: `mid40-1` detection 1.0 -> 1.3 ms; a far marker's hull simplifies to 4)
  int max_hull_vertices = 5;
  double min_hull_fill = 0.5;
  // Above this share of the image, search the whole of it: on busy real scans (Pandar64, regions
  // over 45 %) the split ran no faster than one whole-image call.
  double max_coverage = 0.35;
  // Above this many black-white changes along the rows per pixel, search the whole image without
  // tracing its boundaries (a cluttered scan: 0.035 on the real Pandar64 ones, whose tracing cost
  // 1 ms of their 7.5; the bench scenes 0.0006-0.0035).
  double max_change_density = 0.015;
  // When >= 0, only boundaries whose region (widened by the reach and margin) holds this column
  // are searched (DetectorImages::crossing_column), and a busy image is traced all the same: on
  // the seam strips of real Pandar64 scans, searching the strip whole was a fifth of the pipeline.
  int crossing_column = -1;
};

// True when every pixel of the 8-bit image is 0 or 255.
bool is_binary(const cv::Mat& image);

// A search region, and the shorter side (of the least-area turned rectangle) of the smallest
// boundary in it that no other candidate's box holds (its outermost candidates: markers' borders,
// not the cells inside them); for the whole image, that of all its candidates when they would
// cover too much of it, else 0. A detector may look for quads at a coarser scale in a region of
// large outlines.
struct SearchRegion {
  cv::Rect box;
  int least_outer_side_px = 0;
};

// Disjoint boxes of `binary` (0 or 255) covering every black-white boundary that could be the
// border of a marker, each widened by the rules' reach and margin and aligned to libapriltag's
// 4-pixel threshold tiles, so that the threshold libapriltag computes inside a box is the one it
// computes there on the whole image. A boundary that touches the image edge is left out: a
// marker's border needs white beyond it inside the image. Returns the whole image when the boxes
// would cover more than max_coverage of it or the image changes too often to be worth tracing
// (unless only crossing_column's boundaries are wanted), and nothing when no boundary qualifies.
std::vector<SearchRegion> sized_search_regions(const cv::Mat& binary,
                                               const SearchRegionRules& rules);
// The boxes of sized_search_regions.
std::vector<cv::Rect> search_regions(const cv::Mat& binary, const SearchRegionRules& rules);

// Calls detect_in(part, origin, least_outer_side_px) for each search region of `image` (a copy of
// its pixels in `crop`, whose pixel (0, 0) is `origin` of the image; the image itself when the
// region is all of it), or once for the whole image with 0 when `use` is false or the image is
// not binary.
template <typename DetectIn>
void detect_in_search_regions(const cv::Mat& image, bool use, const SearchRegionRules& rules,
                              cv::Mat& crop, DetectIn&& detect_in) {
  if (!use || !is_binary(image)) {
    detect_in(image, cv::Point(0, 0), 0);
    return;
  }
  for (const SearchRegion& region : sized_search_regions(image, rules)) {
    if (region.box.size() == image.size()) {
      detect_in(image, cv::Point(0, 0), region.least_outer_side_px);
    } else {
      image(region.box).copyTo(crop);
      detect_in(crop, region.box.tl(), region.least_outer_side_px);
    }
  }
}

}  // namespace iilfm::detail
