// Dark squares for ring-sample decoding (ring_decoding.hpp): the black square of a marker whose
// code no detector could read is still a dark blob with four straight sides in the binary image.
#pragma once

#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm::detail {

// Outlines of dark blobs (0 = black in `binary`) whose convex hulls are nearly quadrilaterals with
// sides of at least `min_side_px`, and boxes at least `min_height_px` tall (`min_side_px` when not
// given: a far square's top or bottom border row that no ring crossed is missing from `binary`).
// Each side is a line fitted to the outline's outer envelope along it (white data cells next to a
// border row no ring crossed notch the outline); corners are the lines' intersections, clockwise on
// the screen (y down), any corner first. Where two opposite fitted sides turn from parallel by
// more than 8 degrees, the square follows a second time, the worse fitted of the two laid
// parallel to its opposite.
//
// Where the rings are sparse, white data cells can also cut the black square in two (a white path
// from a missing border row through the data to a gap in the other border) or cut a corner piece
// off it: two dark blobs no farther apart than half a cell (of a square `cells` cells across their
// joint box) are also tried as one; `cells` 0 tries none.
std::vector<std::array<Vec2, 4>> dark_quads(const cv::Mat& binary, double min_side_px, int cells,
                                            std::optional<double> min_height_px = std::nullopt);

}  // namespace iilfm::detail
