#include "iilfm/apriltag_families.hpp"

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

#include <cstdlib>
#include <memory>

#include "iilfm/error.hpp"

namespace iilfm {

namespace {

// Debian's libapriltag does not export image_u8_destroy (it lives in libapriltag-utils); the image
// is two malloc'd blocks, pixels and header, so free them as it would.
void free_image(image_u8_t* image) {
  if (image == nullptr) return;
  std::free(image->buf);
  std::free(image);
}

}  // namespace

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

AprilTagImage render_apriltag(const std::string& name, int id) {
  const AprilTagFamilyEntry* entry = find_apriltag_family(name);
  if (!entry) throw InputError("unknown AprilTag family '" + name + "'");
  std::unique_ptr<apriltag_family_t, void (*)(apriltag_family_t*)> family(entry->create(),
                                                                          entry->destroy);
  if (id < 0 || static_cast<std::uint32_t>(id) >= family->ncodes) {
    throw InputError("marker id " + std::to_string(id) + " is outside apriltag:" + name +
                     " (ids 0.." + std::to_string(family->ncodes - 1) + ")");
  }
  std::unique_ptr<image_u8_t, void (*)(image_u8_t*)> image(apriltag_to_image(family.get(), id),
                                                           free_image);
  AprilTagImage out;
  out.total_width = family->total_width;
  out.width_at_border = family->width_at_border;
  out.pixels.resize(static_cast<std::size_t>(image->width) * image->height);
  for (int row = 0; row < image->height; ++row)
    for (int col = 0; col < image->width; ++col)
      out.pixels[static_cast<std::size_t>(row) * image->width + col] =
          image->buf[row * image->stride + col];
  return out;
}

}  // namespace iilfm
