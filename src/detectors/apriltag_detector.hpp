// AprilTag 3 back-end through libapriltag.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "iilfm/detector.hpp"

namespace iilfm::detail {

// `tag_family` is libapriltag's name ("tag36h11"); InputError if it does not ship it.
std::unique_ptr<MarkerDetector> make_apriltag_detector(const std::string& tag_family,
                                                       const AprilTagOptions& options);

// Per-family default of bits to correct: enough to survive LiDAR noise, few enough to keep
// small families (tag16h5) from decoding noise and big ones quick to set up.
int default_max_hamming(int family_min_distance, std::uint32_t family_codes);

FamilyLayout apriltag_layout(const std::string& tag_family);

}  // namespace iilfm::detail
