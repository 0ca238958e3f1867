// Ready-made scenes with the LiDAR placed for them, shared by `iilfm sim`, tests and benchmarks.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "iilfm/sim/scene.hpp"
#include "iilfm/types.hpp"

namespace iilfm::sim {

// Leave a field empty for the scene's own default.
struct SceneParams {
  std::optional<std::string> family;    // marker family of every marker in the scene
  std::optional<int> id;                // marker id (grid: id of the top-left marker)
  std::optional<double> marker_size_m;  // edge of the outer black square
  std::optional<double> distance_m;  // LiDAR to wall (tag-wall, grid, around), to marker (ccw10m)
};

struct SceneSetup {
  Scene scene;
  Isometry3 T_world_lidar = Isometry3::Identity();
  std::string sensor;  // the sensor the scene was made for
};

// "tag-wall": the paper's set-up, a 17.2 cm tag36h11 id 0 centred at (3.62, 0, 0.485) on a wall
//   facing -x, floor at z = 0, a Mid-40 level with the tag 2 m in front of it (markers larger
//   than 0.5 m are raised to 0.75 x size + 0.1 m so their sheet clears the floor).
// "grid": 7 x 5 tag36h11 ids 0..34 of 17.2 cm on letter-size pitch around the same centre, 3.5 m.
// "paper-grid": the paper's Fig. 1(a) and 8(a), the 35 tags of "grid" and four 16 cm
//   DICT_4X4_50 ArUco markers (ids 0..3, 2 x 2) to their right on the same wall, 4 m; family, id
//   and size are fixed.
// "ccw10m": LiDARTag's ccw_10m set-up, a ULTRA Puck at the origin and a tag16h5 on a 1.22 m board
//   (0.915 m black square) 10 m ahead, turned about 45 deg in its plane, on a wall yawed 23.4 deg
//   and leaning back 8.9 deg.
// "room": data/scenes/room.yaml: an 8 x 6 x 3 m room with a box, four markers (ids id..id+3, 0.3
//   m) on the front and left walls and the box, an Avia turned towards the front-left corner.
// "around": data/scenes/around.yaml: five 0.5 m markers on the four walls of a square room
//   around an OS1-64; distance = LiDAR to each wall (5 m).
// InputError naming the known scenes for anything else.
SceneSetup named_scene(const std::string& name, const SceneParams& params = {});

std::vector<std::string> named_scene_names();

}  // namespace iilfm::sim
