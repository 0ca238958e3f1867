// Reads a square marker's cells from the pixels the LiDAR measured, not from an interpolated image.
// On a spinning LiDAR far from the marker, fewer rings cross it than it has cell rows: cells no
// ring crossed near their middle are erasures, and every read cell comes from real returns.
#pragma once

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "cell_code_book.hpp"
#include "iilfm/projection.hpp"
#include "iilfm/types.hpp"

namespace iilfm::detail {

struct CellReadOptions;
struct CellReading;

// Columns are the coarse axis of `g` when they lie more than this many times farther apart than
// its rows (an OS2-128 at 1024 columns: 0.35 deg columns, 0.18 deg rings).
inline constexpr double kCoarseColumnsRatio = 1.5;

// True when `g`'s columns are much coarser than its rows (res_v, the mean ring spacing on ring
// rows): a marker's placing is then searched along the image's horizontal instead of its vertical
// (MarkerSamples).
bool columns_are_coarse(const ImageGeometry& g);

// The measured pixels around a marker, placed in its plane. The marker's image is modelled in the
// tangent plane of the LiDAR's view sphere at the marker (a pinhole view, where a planar square
// maps through a homography), so ring elevations and column azimuths enter exactly. The plane's
// "vertical" (b, along which placings shift the top and bottom sides) is the image's coarse axis:
// its vertical on most spinning LiDARs, its horizontal turned a quarter turn where the columns
// are the coarse axis (columns_are_coarse): the sides a placing moves are then the right ("top")
// and left ("bottom") ones, and "down" is to the left.
class MarkerSamples {
 public:
  MarkerSamples() = default;  // no samples
  // `corners_px`: the black square's corners in the projected image, in the canonical order
  // (top-left, top-right, bottom-right, bottom-left of the print as seen); `intensity`: CV_32F,
  // the projected image's size. Empty when the corners are degenerate.
  MarkerSamples(const std::array<Vec2, 4>& corners_px, const ProjectedImage& image,
                const cv::Mat& intensity, const CellCodeBook& book);

  bool empty() const { return a_.empty(); }
  std::size_t size() const { return a_.size(); }

  // Where each sample lies on the print when the black square's top side is moved by `shift_top`
  // and its bottom side by `shift_bottom` cell heights along the image's vertical (down
  // positive): column and row of the printed image in cells (the black square spans [start,
  // start + border_width]). With read_cells, the plain statement of a reading: the pipeline
  // reads through fixed_agreement and read, which the tests check against these two.
  struct Placed {
    double col, row;
    float intensity;
  };
  void place(double shift_top, double shift_bottom, std::vector<Placed>& out) const;

  // What read_cells(place(shift_top, shift_bottom)) says of the fixed cells alone: the share of
  // them that read right, or -1 when its levels are not ok. The search over placings calls this
  // hundreds of times per quad, so it skips the data cells and keeps its buffers in `scratch`.
  struct Scratch {
    std::vector<double> sum;
    std::vector<int> count;
    std::vector<float> black, white;
    std::vector<std::int32_t> cell;  // each sample's cell index, -1 when it counts for none
  };
  double fixed_agreement(double shift_top, double shift_bottom, const CellCodeBook& book,
                         const CellReadOptions& options, Scratch& scratch) const;

  // read_cells(place(shift_top, shift_bottom)) with its buffers in `scratch` and the placing
  // vectorised: the candidates' tied placings are each read whole.
  CellReading read(double shift_top, double shift_bottom, const CellCodeBook& book,
                   const CellReadOptions& options, Scratch& scratch) const;

  // The samples that can fall in the middle `central_fraction` of a fixed cell at some placing
  // that moves the whole square by a shift in [lowest, highest] cells (shift_top == shift_bottom),
  // in their order: fixed_agreement gives the same at those placings from them alone. Moving the
  // quad moves a sample's place on the print along a straight segment (a homography maps the
  // line it moves along in the tangent plane to a line), so the box of the segment's ends, widened
  // by a hundredth of a cell for rounding, bounds every place it takes. Most samples lie in the
  // data cells or outside the print at every such placing.
  MarkerSamples fixed_cell_samples(double lowest, double highest, const CellCodeBook& book,
                                   double central_fraction) const;
  // The same for placings that move the top side by a shift in `top` and the bottom side by one
  // in `bottom`, independently (the ring candidates' search). A sample's place on the print moves
  // monotonically with each side's shift while the other stays (exactly so where the quad is an
  // affine image of the square; tested on perspective ones), so the box of its places at the four
  // corner placings bounds every place it takes.
  struct ShiftRange {
    double lowest, highest;
  };
  MarkerSamples fixed_cell_samples(ShiftRange top, ShiftRange bottom, const CellCodeBook& book,
                                   double central_fraction) const;

  // The black square's corners in the projected image of geometry `g` (the one the samples came
  // from) at the placing (shift_top, shift_bottom), in the order and on the side of a full-circle
  // image's seam of the corners given.
  std::array<Vec2, 4> corners_at(double shift_top, double shift_bottom,
                                 const ImageGeometry& g) const;

 private:
  // Each cell's sum and count of the samples in its middle `central_fraction` at the placing, and
  // the fixed cells' samples as black and white levels, into `scratch`; the data cells' only with
  // `data_cells`.
  void sum_cells(double shift_top, double shift_bottom, const CellCodeBook& book,
                 double central_fraction, bool data_cells, Scratch& scratch) const;

  // The samples whose box of places over `bounding_placings` (shift_top, shift_bottom) meets the
  // middle of a fixed cell.
  MarkerSamples fixed_cell_samples(const std::vector<std::pair<double, double>>& bounding_placings,
                                   const CellCodeBook& book, double central_fraction) const;

  // Tangent-plane coordinates (b grows downwards in the image) and intensity of each sample, in
  // separate arrays so the per-placing mapping vectorises.
  std::vector<double> a_, b_;
  std::vector<float> intensity_;
  std::vector<cv::Point2f> quad_;  // the corners in the tangent plane
  Vec3 view_, right_, up_;         // the tangent plane's normal and axes
  double u_corners_ = 0;           // the given corners' mean column
  double cell_height_ = 0;         // tangent units per cell along b
  double start_ = 0;               // printed cell of the black square's corner
  int n_ = 0;                      // cells across the black square
};

struct CellReadOptions {
  // A sample counts for a cell when it lies in the middle `central_fraction` of the cell in both
  // directions: nearer an edge, the beam and the corner's uncertainty may put it in the neighbour.
  double central_fraction = 0.6;
  // A cell whose mean lies within this share of the black-white contrast of the threshold is an
  // erasure rather than a guess.
  double ambiguous_fraction = 0.2;
  // Share of sampled fixed cells (black border, white margin, ...) that must read right.
  double min_fixed_agreement = 0.9;
  int min_fixed_cells = 6;  // of each colour
};

struct CellReading {
  BitReading bits;
  bool levels_ok = false;  // enough fixed cells of each colour, contrast, agreement
  double black = 0, white = 0;
  int fixed_cells = 0, fixed_agreeing = 0;
};

// Reads the cells from placed samples: black and white levels from the fixed cells (the marker's
// own, no global threshold), then each data cell from the mean of its central samples. The
// reference MarkerSamples::read is tested against; the pipeline calls read.
CellReading read_cells(const std::vector<MarkerSamples::Placed>& placed, const CellCodeBook& book,
                       const CellReadOptions& options);

}  // namespace iilfm::detail
