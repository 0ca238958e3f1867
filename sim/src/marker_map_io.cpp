// The scene's markers as a marker map (ARCHITECTURE.md): world corners with 6 decimals.
#include <cmath>
#include <cstdio>
#include <fstream>

#include "iilfm/error.hpp"
#include "iilfm/sim/ground_truth_io.hpp"

namespace iilfm::sim {
namespace {

// Fixed 6 decimals, with values that round to zero printed as 0 rather than -0.
std::string fixed6(double v) {
  double rounded = std::round(v * 1e6) / 1e6;
  if (rounded == 0) rounded = 0;
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6f", rounded);
  return buffer;
}

}  // namespace

void write_marker_map_yaml(const std::string& path, const Scene& scene) {
  std::ofstream out(path);
  if (!out) throw file_error(path, "cannot open for writing");
  out << "# iilfm marker map written by the simulator. Corners in world coordinates (metres):\n"
         "# top-left, top-right, bottom-right, bottom-left of the outer black square.\n";
  if (scene.markers.empty())
    out << "markers: []\n";
  else
    out << "markers:\n";
  for (const MarkerSpec& m : scene.markers) {
    out << "  - family: " << m.family << "\n"
        << "    id: " << m.id << "\n"
        << "    corners:\n";
    for (const Vec3& c : marker_corners_world(m)) {
      out << "      - [" << fixed6(c.x()) << ", " << fixed6(c.y()) << ", " << fixed6(c.z())
          << "]\n";
    }
  }
  if (!out) throw file_error(path, "write failed");
}

}  // namespace iilfm::sim
