// Maps "backend:family" strings to back-ends. A new back-end adds one row to backends().
#include <string>

#include "apriltag_detector.hpp"
#include "aruco_detector.hpp"
#include "aruco_dictionaries.hpp"
#include "charuco_detector.hpp"
#include "iilfm/apriltag_families.hpp"
#include "iilfm/detector.hpp"
#include "iilfm/error.hpp"
#include "rings_detector.hpp"

namespace iilfm {

namespace {

// What the registry needs of a back-end; `family` arguments come without the "backend:" prefix.
struct Backend {
  const char* name;
  std::unique_ptr<MarkerDetector> (*make)(const std::string& family, const DetectorOptions&);
  std::vector<std::string> (*families)();
  FamilyLayout (*layout)(const std::string& family);
};

const std::vector<Backend>& backends() {
  static const std::vector<Backend> table = {
      {"apriltag",
       [](const std::string& f, const DetectorOptions& o) {
         return detail::make_apriltag_detector(f, o.apriltag);
       },
       [] {
         std::vector<std::string> names;
         for (const auto& entry : apriltag_families()) names.emplace_back(entry.name);
         return names;
       },
       detail::apriltag_layout},
      {"aruco",
       [](const std::string& f, const DetectorOptions& o) {
         return detail::make_aruco_detector(f, o.aruco);
       },
       [] {
         std::vector<std::string> names;
         for (const auto& entry : detail::aruco_dictionaries()) names.emplace_back(entry.name);
         return names;
       },
       detail::aruco_layout},
      {"charuco",
       [](const std::string& f, const DetectorOptions& o) {
         return detail::make_charuco_detector(f, o.aruco);
       },
       detail::charuco_example_families, detail::charuco_layout},
      {"rings",
       [](const std::string& f, const DetectorOptions& o) {
         return detail::make_rings_detector(f, o.rings);
       },
       detail::rings_families_names, detail::rings_layout},
  };
  return table;
}

struct FamilyName {
  const Backend* backend;
  std::string family;
};

FamilyName split_family(const std::string& name) {
  const auto colon = name.find(':');
  if (colon == std::string::npos) {
    std::string hint = " (expected BACKEND:FAMILY, e.g. apriltag:tag36h11)";
    for (const Backend& b : backends())
      for (const std::string& f : b.families())
        if (f == name) hint = " (did you mean '" + std::string(b.name) + ":" + name + "'?)";
    throw InputError("unknown marker family '" + name + "'" + hint);
  }
  const std::string backend = name.substr(0, colon);
  std::string available;
  for (const Backend& b : backends()) {
    if (backend == b.name) return {&b, name.substr(colon + 1)};
    available += (available.empty() ? "" : ", ") + std::string(b.name);
  }
  throw InputError("unknown marker back-end '" + backend + "' in '" + name +
                   "' (available: " + available + ")");
}

}  // namespace

std::unique_ptr<MarkerDetector> make_detector(const std::string& family,
                                              const DetectorOptions& options) {
  const FamilyName name = split_family(family);
  return name.backend->make(name.family, options);
}

std::vector<std::string> known_families() {
  std::vector<std::string> names;
  for (const Backend& b : backends())
    for (const std::string& f : b.families()) names.push_back(std::string(b.name) + ":" + f);
  return names;
}

FamilyLayout family_layout(const std::string& family) {
  const FamilyName name = split_family(family);
  return name.backend->layout(name.family);
}

}  // namespace iilfm
