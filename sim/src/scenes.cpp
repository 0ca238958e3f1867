// Named scenes: the paper's single-tag and grid set-ups, LiDARTag's ccw_10m benchmark, and the
// rooms of room_scenes.cpp.
#include "iilfm/sim/scenes.hpp"

#include <algorithm>
#include <cmath>

#include "iilfm/error.hpp"
#include "iilfm/sim/marker_texture.hpp"
#include "room_scenes.hpp"

namespace iilfm::sim {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// The paper's MoCap set-up: the tag centre at (3.620, 0.00, 0.485) m in the world.
constexpr double kPaperWallX = 3.62;
constexpr double kPaperTagZ = 0.485;

void check_distance(double distance) {
  if (!(distance > 0)) {
    throw InputError("scene distance must be positive, got " + std::to_string(distance));
  }
}

Isometry3 level_lidar_at(const Vec3& position) {
  Isometry3 T = Isometry3::Identity();
  T.translation() = position;
  return T;
}

SceneSetup tag_wall(const SceneParams& p) {
  const double distance = p.distance_m.value_or(2.0);
  check_distance(distance);
  const double size = p.marker_size_m.value_or(0.172);
  // The paper's height, raised for large markers so the printed sheet clears the floor.
  const double centre_z = std::max(kPaperTagZ, 0.75 * size + 0.1);
  const MarkerSpec tag = wall_marker(p.family.value_or("apriltag:tag36h11"), p.id.value_or(0), size,
                                     kPaperWallX, 0, centre_z);
  SceneSetup setup;
  setup.scene = wall_scene({tag}, kPaperWallX);
  setup.T_world_lidar = level_lidar_at(Vec3(kPaperWallX - distance, 0, centre_z));
  setup.sensor = "mid40";
  return setup;
}

// The paper's tag grid: 7 x 5 letter-size sheets (a 17.2 cm tag36h11 prints 21.5 cm wide), sheets
// 16 % wider than the print apart, ids row by row from the top-left as the viewer sees it.
constexpr int kGridColumns = 7, kGridRows = 5;

struct TagGrid {
  std::vector<MarkerSpec> markers;
  double pitch = 0;     // sheet to sheet, metres
  double centre_z = 0;  // height of the grid's centre
};

TagGrid tag_grid(const std::string& family, int first_id, double size) {
  const MarkerTexture texture = render_marker_texture(family, first_id);
  render_marker_texture(family, first_id + kGridColumns * kGridRows - 1);  // every id exists
  TagGrid grid;
  grid.pitch = 1.16 * size * texture.total_width / texture.width_at_border;
  // Centred high enough that the bottom row's sheets clear the floor at z = 0.
  grid.centre_z = std::max(kPaperTagZ, (kGridRows / 2.0) * grid.pitch + 0.05);
  for (int row = 0; row < kGridRows; ++row) {
    for (int col = 0; col < kGridColumns; ++col) {
      const double y = ((kGridColumns - 1) / 2.0 - col) * grid.pitch;  // to the viewer's right
      const double z = grid.centre_z + ((kGridRows - 1) / 2.0 - row) * grid.pitch;
      grid.markers.push_back(
          wall_marker(family, first_id + row * kGridColumns + col, size, kPaperWallX, y, z));
    }
  }
  return grid;
}

SceneSetup grid(const SceneParams& p) {
  const double distance = p.distance_m.value_or(3.5);  // whole grid inside the Mid-40 cone
  check_distance(distance);
  const TagGrid tags = tag_grid(p.family.value_or("apriltag:tag36h11"), p.id.value_or(0),
                                p.marker_size_m.value_or(0.172));
  SceneSetup setup;
  setup.scene = wall_scene(tags.markers, kPaperWallX);
  setup.T_world_lidar = level_lidar_at(Vec3(kPaperWallX - distance, 0, tags.centre_z));
  setup.sensor = "mid40";
  return setup;
}

// The paper's Fig. 1(a) and 8(a): the 35-tag grid and, on the same wall, a grid of four 16 cm 4x4
// ArUco markers (the paper names neither the dictionary nor the layout: DICT_4X4_50 ids 0..3, two
// by two on the tags' sheet pitch, to the viewer's right of the tags, level with the grid's middle,
// with a quarter pitch more gap). The LiDAR faces the middle of the whole arrangement.
SceneSetup paper_grid(const SceneParams& p) {
  if (p.family || p.id || p.marker_size_m) {
    throw InputError(
        "scene 'paper-grid' prints the paper's markers; family, id and size are fixed");
  }
  const double distance = p.distance_m.value_or(4.0);  // both grids inside the Mid-40 cone
  check_distance(distance);
  TagGrid tags = tag_grid("apriltag:tag36h11", 0, 0.172);
  const double first_aruco_y = -((kGridColumns - 1) / 2.0 + 1.25) * tags.pitch;
  for (int row = 0; row < 2; ++row) {
    for (int col = 0; col < 2; ++col) {
      tags.markers.push_back(wall_marker("aruco:DICT_4X4_50", row * 2 + col, 0.16, kPaperWallX,
                                         first_aruco_y - col * tags.pitch,
                                         tags.centre_z + (0.5 - row) * tags.pitch));
    }
  }
  const double left = (kGridColumns - 1) / 2.0 * tags.pitch, right = first_aruco_y - tags.pitch;
  SceneSetup setup;
  setup.scene = wall_scene(tags.markers, kPaperWallX);
  setup.T_world_lidar =
      level_lidar_at(Vec3(kPaperWallX - distance, (left + right) / 2, tags.centre_z));
  setup.sensor = "mid40";
  return setup;
}

// LiDARTag's ccw_10m: a tag16h5 on a 1.22 m board (tag16h5 prints 8 cells, the black square 6,
// so its vertices are 0.915 m apart) 10 m ahead of an ULTRA Puck, turned about 45 deg (50.8 deg
// from the board's up direction) in its plane.
// The board's normal points 23.4 deg to the side and 8.9 deg up, which puts its vertices in the
// LiDAR frame near the published ground truth (9.74, 0.76, -0.16), (9.94, 0.07, -0.73),
// (10.27, -0.41, -0.03), (10.07, 0.27, 0.54).
SceneSetup ccw10m(const SceneParams& p) {
  const Vec3 published_centre(10.005, 0.1725, -0.095);
  const double distance = p.distance_m.value_or(published_centre.norm());
  check_distance(distance);
  const Vec3 centre = published_centre.normalized() * distance;
  const Mat3 turned = (Eigen::AngleAxisd(23.4 * kDegToRad, Vec3::UnitZ()) *
                       Eigen::AngleAxisd(8.9 * kDegToRad, Vec3::UnitY()))
                          .toRotationMatrix() *
                      facing_minus_x();

  MarkerSpec tag;
  tag.family = p.family.value_or("apriltag:tag16h5");
  tag.id = p.id.value_or(0);
  tag.size_m = p.marker_size_m.value_or(1.22 * 6.0 / 8.0);
  tag.T_world_marker.linear() =
      turned * Eigen::AngleAxisd(50.8 * kDegToRad, Vec3::UnitZ()).toRotationMatrix();
  tag.T_world_marker.translation() = centre;

  constexpr double kFloorZ = -1.0;  // the sensor on a tripod about 1 m up
  Wall wall;
  wall.width_m = 6;
  wall.height_m = 3;
  wall.reflectivity = 60;
  wall.T_world_wall.linear() = turned;
  // Raised so that its lower edge meets the floor near the marker.
  const Vec3 up = turned.col(1);
  wall.T_world_wall.translation() =
      centre + up * (wall.height_m / 2 + (kFloorZ - centre.z()) / up.z());

  Wall floor;
  floor.width_m = 2 * distance + 4;
  floor.height_m = 2 * distance + 4;
  floor.reflectivity = 25;
  floor.T_world_wall.translation() = Vec3(0, 0, kFloorZ);

  SceneSetup setup;
  setup.scene.walls = {wall, floor};
  setup.scene.markers = {tag};
  setup.T_world_lidar = Isometry3::Identity();
  setup.sensor = "ultrapuck";
  return setup;
}

}  // namespace

std::vector<std::string> named_scene_names() {
  return {"tag-wall", "grid", "ccw10m", "room", "around", "paper-grid"};
}

SceneSetup named_scene(const std::string& name, const SceneParams& params) {
  if (name == "tag-wall") return tag_wall(params);
  if (name == "grid") return grid(params);
  if (name == "paper-grid") return paper_grid(params);
  if (name == "ccw10m") return ccw10m(params);
  if (name == "room") return room_scene(params);
  if (name == "around") return around_scene(params);
  std::string known;
  for (const std::string& n : named_scene_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown simulated scene '" + name + "' (known: " + known + ")");
}

}  // namespace iilfm::sim
