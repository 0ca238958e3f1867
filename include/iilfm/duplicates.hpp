// One report per physical marker when several back-ends decode it (e.g. apriltag:tag36h11 and
// aruco:DICT_APRILTAG_36h11 on the same tag).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "iilfm/detector.hpp"

namespace iilfm {

// Intersection over union of two detections' outlines in the image (0 when either is degenerate).
double outline_overlap(const Detection& a, const Detection& b);

// Keeps one of every pair of detections from different families whose outlines overlap by at
// least `min_overlap` (intersection over union): the one `preferred` says yes to when only one of
// them is (e.g. the one in the marker map), otherwise the earlier one, i.e. the family listed
// first. Detections of the same family are never merged. Returns how many were dropped.
std::size_t drop_duplicate_detections(std::vector<Detection>& detections,
                                      const std::function<bool(const Detection&)>& preferred = {},
                                      double min_overlap = 0.5);

}  // namespace iilfm
