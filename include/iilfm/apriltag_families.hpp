// libapriltag's families by name (creation, destruction) and their official rendering, shared by
// the detector back-end, the simulator and the tests.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

struct apriltag_family;

namespace iilfm {

struct AprilTagFamilyEntry {
  const char* name;  // libapriltag's name, e.g. "tag36h11"
  apriltag_family* (*create)();
  void (*destroy)(apriltag_family*);
};

// The nine families libapriltag ships.
const std::vector<AprilTagFamilyEntry>& apriltag_families();
const AprilTagFamilyEntry* find_apriltag_family(const std::string& name);

// A tag as libapriltag's apriltag_to_image prints it: one pixel per cell.
struct AprilTagImage {
  int total_width = 0;               // image side in cells, white quiet zone included
  int width_at_border = 0;           // cells spanned by the outer black square
  std::vector<std::uint8_t> pixels;  // total_width^2, row 0 = top of the printed tag; 0 = black
};

// InputError for unknown families (libapriltag's name, no prefix) and ids outside the family.
AprilTagImage render_apriltag(const std::string& name, int id);

}  // namespace iilfm
