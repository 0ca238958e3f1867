// Ground truth and marker maps on disk: the truth as JSON, the scene's markers as a marker map.
#pragma once

#include <string>

#include "iilfm/sim/scene.hpp"
#include "iilfm/sim/simulate.hpp"

namespace iilfm::sim {

// {"sensor", "frames", "seed", "range_sigma_m", "T_world_lidar" (4x4 row-major), "markers": [{
// "family", "id", "size_m", "visible", "points_on_marker", "corners_world", "corners_lidar",
// "T_world_marker", "T_lidar_marker"}]}. InputError if the file cannot be written.
void write_ground_truth_json(const std::string& path, const GroundTruth& truth);

// Reads what write_ground_truth_json wrote. InputError("<path>: <problem>") on a bad file.
GroundTruth read_ground_truth_json(const std::string& path);

// The marker map of docs (ARCHITECTURE.md): family, id and the four world corners (top-left,
// top-right, bottom-right, bottom-left) of every marker, 6 decimals.
void write_marker_map_yaml(const std::string& path, const Scene& scene);

}  // namespace iilfm::sim
