// AprilTag images straight from libapriltag, so the simulated print is exactly what the family's
// own generator prints and what the detector expects.
#include "iilfm/sim/marker_texture.hpp"

#include "iilfm/apriltag_families.hpp"
#include "iilfm/error.hpp"

namespace iilfm::sim {
namespace {

constexpr const char* kPrefix = "apriltag:";

std::string known_families() {
  std::string known;
  for (const std::string& n : apriltag_family_names()) known += (known.empty() ? "" : ", ") + n;
  return known;
}

}  // namespace

std::vector<std::string> apriltag_family_names() {
  std::vector<std::string> names;
  for (const AprilTagFamilyEntry& entry : apriltag_families())
    names.push_back(std::string(kPrefix) + entry.name);
  return names;
}

MarkerTexture render_marker_texture(const std::string& family, int id) {
  const std::string prefix = kPrefix;
  const bool apriltag = family.compare(0, prefix.size(), prefix) == 0;
  const std::string name = apriltag ? family.substr(prefix.size()) : family;
  if (!apriltag || !find_apriltag_family(name)) {
    throw InputError("the simulator cannot print marker family '" + family +
                     "' (known: " + known_families() + ")");
  }
  AprilTagImage image = render_apriltag(name, id);
  MarkerTexture texture;
  texture.total_width = image.total_width;
  texture.width_at_border = image.width_at_border;
  texture.pixels = std::move(image.pixels);
  return texture;
}

}  // namespace iilfm::sim
