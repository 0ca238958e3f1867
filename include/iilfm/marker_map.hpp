// The marker map: where each marker's corners are in the world (ARCHITECTURE.md "Marker map").
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm {

struct MapMarker {
  std::string family;  // "apriltag:tag36h11"
  int id = 0;
  std::array<Vec3, 4> corners_world;  // top-left, top-right, bottom-right, bottom-left
  double size = 0;                    // edge length, metres (mean of the four edges)
  std::string key() const { return family + "/" + std::to_string(id); }
};

struct MapTolerances {
  double planarity_m = 0.005;  // largest distance of a corner from the corners' best-fit plane
  double squareness = 0.02;    // largest relative deviation of an edge or diagonal from square
};

class MarkerMap {
 public:
  // Parses and validates a YAML map; InputError("<path>: marker <family>/<id> (#k): <problem>").
  static MarkerMap load(const std::string& path, const MapTolerances& tolerances = {});
  // Validates and adds one marker; `where` prefixes error messages.
  void add(const MapMarker& marker, const std::string& where = "map",
           const MapTolerances& tolerances = {});

  const MapMarker* find(const std::string& family, int id) const;
  const std::vector<MapMarker>& markers() const { return markers_; }
  bool empty() const { return markers_.empty(); }

 private:
  std::vector<MapMarker> markers_;
};

}  // namespace iilfm
