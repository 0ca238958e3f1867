// libapriltag's families by name: creation, destruction and layout.
#pragma once

#include <string>
#include <vector>

struct apriltag_family;

namespace iilfm::detail {

struct AprilTagFamilyEntry {
  const char* name;  // libapriltag's name, e.g. "tag36h11"
  apriltag_family* (*create)();
  void (*destroy)(apriltag_family*);
};

const std::vector<AprilTagFamilyEntry>& apriltag_families();
const AprilTagFamilyEntry* find_apriltag_family(const std::string& name);

}  // namespace iilfm::detail
