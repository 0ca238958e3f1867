// Marker geometry: canonical corners and the walls-and-floor scene most tests and demos use.
#include "iilfm/sim/scene.hpp"

#include <cmath>

namespace iilfm::sim {
namespace {
constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
}  // namespace

std::array<Vec3, 4> marker_corners_local(double size_m) {
  const double h = size_m / 2;
  return {Vec3(-h, h, 0), Vec3(h, h, 0), Vec3(h, -h, 0), Vec3(-h, -h, 0)};
}

std::array<Vec3, 4> marker_corners_world(const MarkerSpec& m) {
  std::array<Vec3, 4> corners = marker_corners_local(m.size_m);
  for (Vec3& c : corners) c = m.T_world_marker * c;
  return corners;
}

Mat3 facing_minus_x(double in_plane_deg) {
  Mat3 upright;
  upright.col(0) = -Vec3::UnitY();  // the viewer looks along +x, so its right is -y
  upright.col(1) = Vec3::UnitZ();
  upright.col(2) = -Vec3::UnitX();
  return upright * Eigen::AngleAxisd(in_plane_deg * kDegToRad, Vec3::UnitZ()).toRotationMatrix();
}

MarkerSpec wall_marker(const std::string& family, int id, double size_m, double wall_x, double y,
                       double z, double in_plane_deg) {
  MarkerSpec m;
  m.family = family;
  m.id = id;
  m.size_m = size_m;
  m.T_world_marker = Isometry3::Identity();
  m.T_world_marker.linear() = facing_minus_x(in_plane_deg);
  m.T_world_marker.translation() = Vec3(wall_x, y, z);
  return m;
}

Wall upright_wall(const Vec3& centre, double facing_azimuth_deg, double width_m, double height_m,
                  float reflectivity) {
  // Facing -x is the orientation markers on the named scenes' walls use; turn it about z.
  const double turn = (facing_azimuth_deg - 180) * kDegToRad;
  Wall w;
  w.T_world_wall.linear() =
      Eigen::AngleAxisd(turn, Vec3::UnitZ()).toRotationMatrix() * facing_minus_x();
  w.T_world_wall.translation() = centre;
  w.width_m = width_m;
  w.height_m = height_m;
  w.reflectivity = reflectivity;
  return w;
}

std::vector<Wall> box_walls(const Vec3& centre, const Vec3& size, double yaw_deg,
                            float reflectivity) {
  const Mat3 yaw = Eigen::AngleAxisd(yaw_deg * kDegToRad, Vec3::UnitZ()).toRotationMatrix();
  std::vector<Wall> walls;
  for (int axis = 0; axis < 3; ++axis) {
    // The face across `axis` spans the other two axes, its normal along `axis`.
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    Mat3 face;
    face.col(0) = yaw.col(a);
    face.col(1) = yaw.col(b);
    face.col(2) = yaw.col(axis);
    for (int sign : {-1, 1}) {
      Wall w;
      w.T_world_wall.linear() = face;
      w.T_world_wall.translation() = centre + sign * size[axis] / 2 * yaw.col(axis);
      w.width_m = size[a];
      w.height_m = size[b];
      w.reflectivity = reflectivity;
      walls.push_back(w);
    }
  }
  return walls;
}

MarkerSpec marker_on_wall(const Wall& wall, const std::string& family, int id, double size_m,
                          double u, double v, double in_plane_deg) {
  MarkerSpec m;
  m.family = family;
  m.id = id;
  m.size_m = size_m;
  m.T_world_marker.translation() = wall.T_world_wall * Vec3(u, v, 0);
  m.T_world_marker.linear() =
      wall.T_world_wall.linear() *
      Eigen::AngleAxisd(in_plane_deg * kDegToRad, Vec3::UnitZ()).toRotationMatrix();
  return m;
}

Scene wall_scene(const std::vector<MarkerSpec>& markers, double wall_x, double floor_z,
                 double wall_width_m, double wall_height_m) {
  constexpr double kFloorDepth = 10;  // how far the floor reaches back from the wall
  Scene scene;
  Wall wall;
  wall.T_world_wall = Isometry3::Identity();
  wall.T_world_wall.linear() = facing_minus_x();
  wall.T_world_wall.translation() = Vec3(wall_x, 0, floor_z + wall_height_m / 2);
  wall.width_m = wall_width_m;
  wall.height_m = wall_height_m;
  wall.reflectivity = 60;  // matt paint: darker than paper, brighter than the printed black
  scene.walls.push_back(wall);

  Wall floor;
  floor.T_world_wall = Isometry3::Identity();
  floor.T_world_wall.translation() = Vec3(wall_x - kFloorDepth / 2, 0, floor_z);
  floor.width_m = kFloorDepth;
  floor.height_m = wall_width_m;
  floor.reflectivity = 25;
  scene.walls.push_back(floor);

  scene.markers = markers;
  return scene;
}

}  // namespace iilfm::sim
