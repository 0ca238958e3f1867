// Test helper: a scene of one bare wall facing the LiDAR.
#pragma once

#include "iilfm/sim/scene.hpp"

namespace iilfm::sim::testing {

// A square wall of side `size_m` in the plane x = distance_m, facing -x (towards a LiDAR at the
// origin looking along +x), no markers.
inline Scene plain_wall(double distance_m, double size_m, float reflectivity) {
  Wall w;
  w.T_world_wall.linear() = facing_minus_x();
  w.T_world_wall.translation() = Vec3(distance_m, 0, 0);
  w.width_m = w.height_m = size_m;
  w.reflectivity = reflectivity;
  Scene scene;
  scene.walls = {w};
  return scene;
}

}  // namespace iilfm::sim::testing
