// AprilTag images straight from libapriltag, so the simulated print is exactly what the family's
// own generator prints and what the detector expects.
#include "iilfm/sim/marker_texture.hpp"

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

namespace iilfm::sim {
namespace {

constexpr const char* kPrefix = "apriltag:";

// image_u8_destroy lives in libapriltag-utils, which apriltag::apriltag does not link; the image
// is two malloc'd blocks (pixels and header), so free them as it would.
void free_image(image_u8_t* image) {
  if (image == nullptr) return;
  std::free(image->buf);
  std::free(image);
}

struct FamilyEntry {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

const FamilyEntry kFamilies[] = {
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

std::string known_families() {
  std::string known;
  for (const std::string& n : apriltag_family_names()) known += (known.empty() ? "" : ", ") + n;
  return known;
}

const FamilyEntry& find_family(const std::string& family) {
  const std::string prefix = kPrefix;
  if (family.compare(0, prefix.size(), prefix) == 0) {
    const std::string name = family.substr(prefix.size());
    for (const FamilyEntry& entry : kFamilies) {
      if (name == entry.name) return entry;
    }
  }
  throw InputError("the simulator cannot print marker family '" + family +
                   "' (known: " + known_families() + ")");
}

}  // namespace

std::vector<std::string> apriltag_family_names() {
  std::vector<std::string> names;
  for (const FamilyEntry& entry : kFamilies) names.push_back(std::string(kPrefix) + entry.name);
  return names;
}

MarkerTexture render_marker_texture(const std::string& family, int id) {
  const FamilyEntry& entry = find_family(family);
  std::unique_ptr<apriltag_family_t, void (*)(apriltag_family_t*)> fam(entry.create(),
                                                                       entry.destroy);
  if (id < 0 || static_cast<std::uint32_t>(id) >= fam->ncodes) {
    throw InputError("marker id " + std::to_string(id) + " is outside " + family + " (ids 0.." +
                     std::to_string(fam->ncodes - 1) + ")");
  }
  std::unique_ptr<image_u8_t, void (*)(image_u8_t*)> image(apriltag_to_image(fam.get(), id),
                                                           free_image);
  MarkerTexture texture;
  texture.total_width = fam->total_width;
  texture.width_at_border = fam->width_at_border;
  texture.pixels.resize(static_cast<std::size_t>(image->width) * image->height);
  for (int row = 0; row < image->height; ++row) {
    for (int col = 0; col < image->width; ++col) {
      texture.pixels[row * image->width + col] = image->buf[row * image->stride + col];
    }
  }
  return texture;
}

}  // namespace iilfm::sim
