// Maps "backend:family" strings to back-ends. A new back-end adds one branch here.
#include <string>

#include "apriltag_detector.hpp"
#include "aruco_detector.hpp"
#include "aruco_dictionaries.hpp"
#include "iilfm/apriltag_families.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"

namespace iilfm {

namespace {

struct FamilyName {
  std::string backend, family;
};

FamilyName split_family(const std::string& name) {
  const auto colon = name.find(':');
  if (colon == std::string::npos) {
    const std::string hint = find_apriltag_family(name) ? " (did you mean 'apriltag:" + name + "'?)"
                             : detail::find_aruco_dictionary(name)
                                 ? " (did you mean 'aruco:" + name + "'?)"
                                 : " (expected BACKEND:FAMILY, e.g. apriltag:tag36h11)";
    throw InputError("unknown marker family '" + name + "'" + hint);
  }
  return {name.substr(0, colon), name.substr(colon + 1)};
}

}  // namespace

std::unique_ptr<MarkerDetector> make_detector(const std::string& family,
                                              const DetectorOptions& options) {
  const FamilyName name = split_family(family);
  if (name.backend == "apriltag")
    return detail::make_apriltag_detector(name.family, options.apriltag);
  if (name.backend == "aruco") return detail::make_aruco_detector(name.family, options.aruco);
  throw InputError("unknown marker back-end '" + name.backend + "' in '" + family +
                   "' (available: apriltag, aruco)");
}

std::vector<std::string> known_families() {
  std::vector<std::string> names;
  for (const auto& entry : apriltag_families())
    names.push_back(std::string("apriltag:") + entry.name);
  for (const auto& entry : detail::aruco_dictionaries())
    names.push_back(std::string("aruco:") + entry.name);
  return names;
}

FamilyLayout family_layout(const std::string& family) {
  const FamilyName name = split_family(family);
  if (name.backend == "apriltag") return detail::apriltag_layout(name.family);
  if (name.backend == "aruco") return detail::aruco_layout(name.family);
  throw InputError("unknown marker back-end '" + name.backend + "' in '" + family + "'");
}

}  // namespace iilfm
