// Writes a scene in the format scene_file_reader.cpp reads: every wall (box faces included) and
// every marker by pose, so any scene built in code can be saved and edited by hand.
#include <fstream>
#include <iomanip>
#include <sstream>

#include "iilfm/error.hpp"
#include "iilfm/sim/scene_file.hpp"
#include "rpy.hpp"

namespace iilfm::sim {
namespace {

std::string list(const Vec3& v) {
  std::ostringstream s;
  s << std::setprecision(9) << std::fixed << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

}  // namespace

void write_scene_yaml(const std::string& path, const SceneSetup& setup) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write the scene file");
  const Scene& scene = setup.scene;
  out << "# iilfm simulator scene (docs/simulator.md)\n";
  out << "lidar:\n  sensor: " << setup.sensor << "\n";
  out << "  position: " << list(setup.T_world_lidar.translation()) << "\n";
  out << "  rpy_deg: " << list(rpy_deg_from_rotation(setup.T_world_lidar.linear())) << "\n";
  out << "print:\n  white: " << scene.white_intensity << "\n  black: " << scene.black_intensity
      << "\n";
  if (!scene.walls.empty()) out << "walls:\n";
  for (const Wall& w : scene.walls) {
    out << "  - centre: " << list(w.T_world_wall.translation()) << "\n";
    out << "    rpy_deg: " << list(rpy_deg_from_rotation(w.T_world_wall.linear())) << "\n";
    out << std::setprecision(9) << "    width: " << w.width_m << "\n    height: " << w.height_m
        << "\n    reflectivity: " << w.reflectivity << "\n";
  }
  if (!scene.markers.empty()) out << "markers:\n";
  for (const MarkerSpec& m : scene.markers) {
    out << "  - family: " << m.family << "\n    id: " << m.id << "\n";
    out << std::setprecision(9) << "    size: " << m.size_m << "\n";
    out << "    pose:\n      position: " << list(m.T_world_marker.translation()) << "\n";
    out << "      rpy_deg: " << list(rpy_deg_from_rotation(m.T_world_marker.linear())) << "\n";
  }
  if (!out) throw InputError(path + ": cannot write the scene file");
}

}  // namespace iilfm::sim
