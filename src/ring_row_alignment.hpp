// Ring rows put each ring's sample in the column nearest its azimuth, but a spinning LiDAR fires
// off the image's column grid: its encoder starts the sweep anywhere, its lasers fire microseconds
// apart or look through fixed horizontal offsets (Velodyne, Hesai), and its columns need not be
// exactly the nominal step. A pixel whose sample lies a fraction of a column off its centre moves
// every edge through it by that fraction (up to half a column: 1.7 cm at 10 m for 0.2 deg
// columns). These helpers keep each sample's own column: the image's values stay the samples'
// (no interpolation, which blurs the cells of far markers), and what reads positions from the
// image uses where its samples lie (docs/pipeline.md, "Samples off the column grid").
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "iilfm/projection.hpp"

namespace iilfm::detail {

// Rows whose single-point pixels all lie within this many columns of their centres count as on
// the grid (an Ouster's destaggered columns, a simulated sweep without stagger).
constexpr float kColumnOffsetTolerance = 0.05f;

// Fills image.column_offset (CV_32F: each single-point pixel's sample, in columns right of its
// centre; 0 elsewhere) when some ring row lies off the grid, and releases it otherwise. `azimuth`
// is every point's azimuth in radians as projected, indexed like image.index.
void measure_column_offsets(const float* azimuth, ProjectedImage& image);

// The intensity with each pixel's value moved to its centre: a pixel whose sample lies off it
// takes the value interpolated between its sample and the neighbour sample on the centre's other
// side. For measuring where an edge lies (edge refinement), not for decoding. Only pixels inside
// `within` are moved: `out` holds image.intensity's values elsewhere, and everywhere when
// image.column_offset is empty.
void intensity_at_centres(const ProjectedImage& image, cv::Mat& out, cv::Rect within);

// The box around `count` points (x: columns, y: rows); nullopt when one of them is not finite.
std::optional<cv::Rect2d> box_around(const Vec2* points, std::size_t count);

// The column offsets of the single-point pixels in the box around some corners (projected image
// coordinates): their mean, and the lowest and highest of the rows' means (all 0 without offsets).
struct ColumnOffsets {
  double mean = 0, lowest_row = 0, highest_row = 0;
};
ColumnOffsets column_offsets_in_box(const ProjectedImage& image, const Vec2* corners,
                                    std::size_t count);

// Moves a detection's corners and outline (projected image coordinates) to where the print's
// edges lie: a detector fits each side through every row's edge samples, so it lies their mean
// offset left of the print's edge. (Moving each corner by the rows' offsets fitted as a line down
// the box, against the slant a VLP-16's rings fired one after another give a side, was worse on
// the ULTRA Puck at 10 m: rotation 0.43 deg against 0.38, 16 seeds.)
void move_to_samples(const ProjectedImage& image, std::vector<Vec2>& corners,
                     std::vector<Vec2>& outline);

// Moves a dark square's hull (dark_quads: its sides through the outermost dark pixels) to where
// the print's edges lie. A hull's left side lies on the row whose samples lie furthest right of
// their centres (its first dark pixel is furthest left), its right side on the row furthest left:
// the leftmost corner moves by the highest row offset, the rightmost by the lowest, those between
// in proportion. (By the mean, a VLP-16's staggered rings biased hulls by 0.1 column.)
void move_hull_to_samples(const ProjectedImage& image, std::array<Vec2, 4>& quad);

}  // namespace iilfm::detail
