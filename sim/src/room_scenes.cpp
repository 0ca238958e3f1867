// Rooms: the scenes of data/scenes/room.yaml and around.yaml built in code, so tests and
// `iilfm sim --scene room` need no data file (a test keeps the two in step).
#include "room_scenes.hpp"

#include "iilfm/error.hpp"

namespace iilfm::sim {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// Azimuths the walls of a room face, looking inwards.
constexpr double kFacingMinusX = 180, kFacingMinusY = -90, kFacingPlusX = 0, kFacingPlusY = 90;

Wall floor_or_ceiling(double z, double length_x, double width_y, float reflectivity, bool ceiling) {
  Wall w;
  w.T_world_wall.translation() = Vec3(0, 0, z);
  if (ceiling) w.T_world_wall.linear() = Vec3(1, -1, -1).asDiagonal();  // front facing down
  w.width_m = length_x;
  w.height_m = width_y;
  w.reflectivity = reflectivity;
  return w;
}

}  // namespace

SceneSetup room_scene(const SceneParams& p) {
  if (p.distance_m) throw InputError("scene 'room' has no distance; move the LiDAR instead");
  const std::string family = p.family.value_or("apriltag:tag36h11");
  const double size = p.marker_size_m.value_or(0.3);
  const int id = p.id.value_or(0);
  SceneSetup setup;
  std::vector<Wall>& walls = setup.scene.walls;
  walls.push_back(upright_wall(Vec3(4, 0, 1.5), kFacingMinusX, 6, 3));  // 0 front
  walls.push_back(upright_wall(Vec3(0, 3, 1.5), kFacingMinusY, 8, 3));  // 1 left
  walls.push_back(upright_wall(Vec3(0, -3, 1.5), kFacingPlusY, 8, 3));  // 2 right
  walls.push_back(upright_wall(Vec3(-4, 0, 1.5), kFacingPlusX, 6, 3));  // 3 back
  walls.push_back(floor_or_ceiling(0, 8, 6, 25, false));
  walls.push_back(floor_or_ceiling(3, 8, 6, 70, true));
  const std::vector<Wall> box = box_walls(Vec3(2, 1, 0.35), Vec3(0.7, 0.7, 0.7), 0, 40);
  setup.scene.markers = {marker_on_wall(walls[0], family, id, size, -1.0, -0.2),
                         marker_on_wall(walls[0], family, id + 1, size, -2.2, 0.5, 30),
                         marker_on_wall(walls[1], family, id + 2, size, 2.0, -0.2),
                         // On the box's -x face, upright and facing the LiDAR (-x).
                         wall_marker(family, id + 3, size, 1.65, 1, 0.35)};
  walls.insert(walls.end(), box.begin(), box.end());
  setup.T_world_lidar.translation() = Vec3(0, 0, 1.3);
  setup.T_world_lidar.linear() =
      Eigen::AngleAxisd(36.87 * kDegToRad, Vec3::UnitZ()).toRotationMatrix();
  setup.sensor = "avia";
  return setup;
}

SceneSetup around_scene(const SceneParams& p) {
  const double d = p.distance_m.value_or(5.0);
  if (!(d > 1))
    throw InputError("scene 'around' needs a distance above 1 m, got " + std::to_string(d));
  const std::string family = p.family.value_or("apriltag:tag36h11");
  const double size = p.marker_size_m.value_or(0.5);
  const int id = p.id.value_or(0);
  SceneSetup setup;
  std::vector<Wall>& walls = setup.scene.walls;
  walls.push_back(upright_wall(Vec3(d, 0, 1.5), kFacingMinusX, 2 * d, 3));  // 0 front
  walls.push_back(upright_wall(Vec3(0, d, 1.5), kFacingMinusY, 2 * d, 3));  // 1 left
  walls.push_back(upright_wall(Vec3(-d, 0, 1.5), kFacingPlusX, 2 * d, 3));  // 2 back
  walls.push_back(upright_wall(Vec3(0, -d, 1.5), kFacingPlusY, 2 * d, 3));  // 3 right
  walls.push_back(floor_or_ceiling(0, 2 * d, 2 * d, 25, false));
  // Level with the LiDAR (1 m up), spread along the walls so no two share an azimuth.
  setup.scene.markers = {marker_on_wall(walls[0], family, id, size, 0, -0.5),
                         marker_on_wall(walls[1], family, id + 1, size, 0.3 * d, -0.5),
                         marker_on_wall(walls[2], family, id + 2, size, 0, -0.5, 45),
                         marker_on_wall(walls[3], family, id + 3, size, -0.3 * d, -0.5),
                         marker_on_wall(walls[0], family, id + 4, size, -0.6 * d, -0.5, 90)};
  setup.T_world_lidar.translation() = Vec3(0, 0, 1.0);
  setup.sensor = "os1-64";
  return setup;
}

}  // namespace iilfm::sim
