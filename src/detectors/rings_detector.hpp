// Concentric-ring markers (include/iilfm/rings_family.hpp): ellipses fitted to the contours of the
// thresholded image, grouped when concentric, decoded from the mean grey of each ring.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "iilfm/detector.hpp"

namespace iilfm::detail {

// `family` is "ring7h3" or "ring9h3"; InputError otherwise.
std::unique_ptr<MarkerDetector> make_rings_detector(const std::string& family,
                                                    const RingsOptions& options);

std::vector<std::string> rings_families_names();

// One ring width is the unit: border_width = rings across the outer diameter, total_width = with
// the quiet zone.
FamilyLayout rings_layout(const std::string& family);

}  // namespace iilfm::detail
