// Scenes in a small YAML file, so users can describe their own rooms (docs/simulator.md).
#pragma once

#include <string>

#include "iilfm/sim/scenes.hpp"

namespace iilfm::sim {

// Reads a scene file: walls, boxes, markers (by pose or on a wall), print intensities, the
// LiDAR pose and sensor. InputError("<path>: <where>: <problem>") for anything it cannot use.
SceneSetup read_scene_yaml(const std::string& path);

// The same from text; `source` names it in error messages.
SceneSetup parse_scene_yaml(const std::string& text, const std::string& source);

// Writes `setup` so that read_scene_yaml gives it back (poses as position + rpy_deg, 9 decimals).
// InputError if the file cannot be written.
void write_scene_yaml(const std::string& path, const SceneSetup& setup);

}  // namespace iilfm::sim
