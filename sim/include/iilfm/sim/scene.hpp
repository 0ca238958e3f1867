// What the simulated LiDAR looks at: flat walls and AprilTag or ArUco markers printed on them.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "iilfm/types.hpp"

namespace iilfm::sim {

struct MarkerSpec {
  std::string family;  // "apriltag:tag36h11" (any libapriltag family) or "aruco:DICT_4X4_50" (any
                       // OpenCV predefined dictionary)
  int id = 0;
  double size_m = 0;  // edge of the outer black square (= width_at_border cells)
  // Marker frame: origin at the centre, x to the marker's right, y up, z out of the printed face
  // toward the viewer.
  Isometry3 T_world_marker = Isometry3::Identity();
};

// A finite rectangle of zero thickness, seen from both sides.
struct Wall {
  Isometry3 T_world_wall = Isometry3::Identity();  // centre; the wall is its local x-y plane
  double width_m = 0, height_m = 0;                // along local x and local y
  float reflectivity = 0;                          // intensity returned by the bare wall
};

struct Scene {
  std::vector<Wall> walls;
  // Printed flush on the walls (no thickness, no clearance), visible from the front only. The
  // printed sheet is the family's whole image (total_width cells, quiet zone included) on white
  // paper; outside it the wall shows.
  std::vector<MarkerSpec> markers;
  float white_intensity = 120, black_intensity = 10;  // printed paper returns (Livox-like 0..255)
};

// Corners of the outer black square in the canonical order top-left, top-right, bottom-right,
// bottom-left as seen by a viewer facing the upright printed marker.
std::array<Vec3, 4> marker_corners_world(const MarkerSpec& m);

// Corners in the marker frame, same order: (-s/2,+s/2,0), (+s/2,+s/2,0), (+s/2,-s/2,0),
// (-s/2,-s/2,0).
std::array<Vec3, 4> marker_corners_local(double size_m);

// Orientation of a marker printed upright on a wall that faces -x (towards a LiDAR at the origin
// looking along +x): marker x = world -y, y = world +z, z = world -x. `in_plane_deg` turns the
// marker counter-clockwise as the viewer sees it.
Mat3 facing_minus_x(double in_plane_deg = 0);

// A marker centred at (wall_x, y, z) on a wall facing -x.
MarkerSpec wall_marker(const std::string& family, int id, double size_m, double wall_x, double y,
                       double z, double in_plane_deg = 0);

// An upright wall (width along the horizontal, height up) centred at `centre` whose front, its
// local +z, faces the horizontal direction at `facing_azimuth_deg` (from +x towards +y).
Wall upright_wall(const Vec3& centre, double facing_azimuth_deg, double width_m, double height_m,
                  float reflectivity = 60);

// The six faces of a box of `size` (along its local x, y, z) centred at `centre` and turned by
// `yaw_deg` about world z: the faces across local x, then y, then z, the minus side first.
std::vector<Wall> box_walls(const Vec3& centre, const Vec3& size, double yaw_deg,
                            float reflectivity);

// A marker printed on the front of `wall`, centred `u` along the wall's local x and `v` along
// its local y from the wall's centre, turned `in_plane_deg` counter-clockwise as the viewer sees
// it (marker x, y = the wall's x, y at 0 deg).
MarkerSpec marker_on_wall(const Wall& wall, const std::string& family, int id, double size_m,
                          double u, double v, double in_plane_deg = 0);

// A big wall in the plane x = wall_x facing -x (towards a LiDAR looking along +x), standing on a
// floor at z = floor_z that reaches 10 m back from the wall, plus the given markers.
Scene wall_scene(const std::vector<MarkerSpec>& markers, double wall_x = 3.62, double floor_z = 0,
                 double wall_width_m = 8, double wall_height_m = 3);

}  // namespace iilfm::sim
