#include "apriltag_families.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>

namespace iilfm::detail {

const std::vector<AprilTagFamilyEntry>& apriltag_families() {
  static const std::vector<AprilTagFamilyEntry> families = {
      {"tag16h5", tag16h5_create, tag16h5_destroy},
      {"tag25h9", tag25h9_create, tag25h9_destroy},
      {"tag36h10", tag36h10_create, tag36h10_destroy},
      {"tag36h11", tag36h11_create, tag36h11_destroy},
      {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
      {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
      {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
      {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
      {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
  };
  return families;
}

const AprilTagFamilyEntry* find_apriltag_family(const std::string& name) {
  for (const AprilTagFamilyEntry& entry : apriltag_families())
    if (name == entry.name) return &entry;
  return nullptr;
}

}  // namespace iilfm::detail
