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

// Per-family default of bits to correct: enough to survive LiDAR noise, few enough that a random
// quad decodes at most once in kMaxChanceMatch tries (4 turns x codes x words within the bits
// corrected, over all 2^bits words) and big families stay quick to set up.
constexpr double kMaxChanceMatch = 2e-4;
int default_max_hamming(int family_min_distance, std::uint32_t family_codes, int family_bits);

// The chance that a random quad decodes to one of `family_codes` codes of `family_bits` bits
// (any of 4 turns) with at most `corrected` bits wrong.
double chance_match(std::uint32_t family_codes, int family_bits, int corrected);

// The most bits up to `most` whose correction keeps chance_match within kMaxChanceMatch; -1 when
// even an exact reading is more likely (tag16h5). default_max_hamming's bound, and the errors a
// reading of gray pixels may have.
int bits_within_chance(std::uint32_t family_codes, int family_bits, int most);

FamilyLayout apriltag_layout(const std::string& tag_family);

}  // namespace iilfm::detail
