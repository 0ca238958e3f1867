// Edge-aware corners: a detector finds a marker's black square where the binary image changes,
// i.e. where the intensity crosses the global threshold. When the beam's footprint averages black
// and white at an edge, that crossing is not at the edge: a threshold nearer black than the middle
// shrinks the square, one nearer white grows it. The edge is where the intensity crosses halfway
// between this marker's own black and white levels; this moves each side there.
#pragma once

#include <vector>

#include "iilfm/projection.hpp"

namespace iilfm {

struct EdgeRefinement {
  bool ok = false;               // false: levels or edges not measurable, corners unchanged
  std::vector<Vec2> corners_px;  // the refined quad (projected-image coordinates)
  double black = 0, white = 0;   // the marker's levels: medians in its border and quiet zone
  double mean_shift_px = 0;      // mean outward move of the four sides (negative: inwards)
};

// `corners_px`: the detected quad (4 corners, projected-image coordinates); `border_cells`: the
// black square's width in cells (8 for tag36h11), so that the border and the one-cell white quiet
// zone around it can be sampled. Each side moves by the median over its length of where the
// intensity profile across it crosses (black + white) / 2, at most half a cell; the new corners
// are where adjacent sides meet. Markers with under 4 pixels per cell across a side are left as
// detected (ok = false): the profile is too coarse to place the crossing.
EdgeRefinement refine_edges_to_mid_level(const std::vector<Vec2>& corners_px,
                                         const ProjectedImage& image, int border_cells);

}  // namespace iilfm
