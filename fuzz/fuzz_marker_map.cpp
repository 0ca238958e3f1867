// Fuzz target: the marker map YAML loader on arbitrary bytes. InputError is the one accepted
// failure (a yaml-cpp exception escaping would be a bug); a loaded map's markers must have finite
// corners and a positive size.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "fuzz_input.hpp"
#include "iilfm/error.hpp"
#include "iilfm/marker_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static iilfm::fuzz::ScratchFile scratch;
  scratch.path = iilfm::fuzz::write_input(data, size, ".yaml");
  try {
    const iilfm::MarkerMap map = iilfm::MarkerMap::load(scratch.path);
    for (const iilfm::MapMarker& marker : map.markers()) {
      bool sane = std::isfinite(marker.size) && marker.size > 0;
      for (const iilfm::Vec3& corner : marker.corners_world) sane = sane && corner.allFinite();
      if (!sane) {
        std::fprintf(stderr, "map invariant broken: marker %s\n", marker.key().c_str());
        std::abort();
      }
    }
  } catch (const iilfm::InputError&) {
  }
  return 0;
}
