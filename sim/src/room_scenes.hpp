// Internal: the named scenes with whole rooms, the same as data/scenes/room.yaml and around.yaml.
#pragma once

#include "iilfm/sim/scenes.hpp"

namespace iilfm::sim {

// "room": an 8 x 6 x 3 m room, a box, four markers on two walls and the box, an Avia turned
// towards the front-left corner. No distance parameter.
SceneSetup room_scene(const SceneParams& params);

// "around": markers on all four walls of a square room around an OS1-64; distance = LiDAR to
// each wall (default 5 m).
SceneSetup around_scene(const SceneParams& params);

}  // namespace iilfm::sim
