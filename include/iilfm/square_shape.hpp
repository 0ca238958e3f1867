// How square a marker's lifted corners are. A printed square seen from anywhere lifts to a square
// in 3-D; a detector's chance match on noise (a quad of speckle that happens to decode) lifts to
// whatever quadrilateral the speckle drew.
#pragma once

#include <array>

#include "iilfm/types.hpp"

namespace iilfm {

struct SquareShape {
  double side_m = 0;           // edge of the nearest square
  double rms_m = 0;            // RMS distance of the corners from that square's corners
  Vec3 centre = Vec3::Zero();  // the square's centre (the corners' mean)
};

// The square of any size, turn and place nearest (least squares) to four corners given in order
// around it, and how far they lie from it.
SquareShape nearest_square(const std::array<Vec3, 4>& corners);

}  // namespace iilfm
