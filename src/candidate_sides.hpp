// The left and right sides of a ring candidate (ring_decoding.hpp), measured on the rings that
// cross them. A dark quad's sides come from the binary image, so they lie on pixel edges: up to
// most of a pixel from the printed edge, a third of a cell where a marker spans 1.4 columns a cell
// (an OS1-64's 40 cm tag at 6 m). The pixel the edge crosses holds a mix of black and white, and
// its level says where the edge lies within it.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <optional>

#include "iilfm/projection.hpp"
#include "iilfm/types.hpp"

namespace iilfm::detail {

// Which way each side of `corners` (side k runs from corner k to corner k + 1) faces along the
// rows: -1 the left side, +1 the right one, 0 the top or bottom (a side nearer the horizontal).
std::array<int, 4> side_facings(const std::array<Vec2, 4>& corners);

// `corners` with the left side moved `left` and the right side `right` pixels along the rows, each
// side's ends with it.
std::array<Vec2, 4> sides_moved(const std::array<Vec2, 4>& corners, double left, double right);

// `corners` (projected image, a quadrilateral) with its left and right sides turned about their
// middles to meet the mean direction of its top and bottom ones at right angles, angles measured
// with a column `column_angle` and a row `row_angle` wide. Where the columns are coarse, the
// binary image's left and right outlines are ragged by a column and their fitted sides lean
// (an OS2-128's 17 cm tag at 4 m: 7 columns and 14 rings, sides leaning by 1-2 columns), while a
// square's sides meet square in any view but a strongly oblique and turned one. nullopt when the
// quad has no two top and bottom sides or the lines do not meet.
std::optional<std::array<Vec2, 4>> squared_left_right_sides(const std::array<Vec2, 4>& corners,
                                                            double column_angle, double row_angle);

// `corners` (projected image, a quadrilateral) with each near-vertical side moved along the rows to
// where the rows it spans step up across their own mid level going outwards from the black border
// (midway between a row's darkest pixel within a pixel and a half of the side and its brightest
// beyond that): the median over those rows, each crossing interpolated linearly between the two
// pixel centres around it, and at most `max_shift_px` from where the side was. `black` and `white`
// are the marker's levels: a row counts when its step spans half their difference and its darkest
// pixel lies below their middle. Needs two such rows per side; nullopt when a side has fewer or
// the levels are not apart.
std::optional<std::array<Vec2, 4>> measured_side_columns(const std::array<Vec2, 4>& corners,
                                                         const ProjectedImage& image,
                                                         const cv::Mat& intensity, double black,
                                                         double white, double max_shift_px = 1);

}  // namespace iilfm::detail
