// The LiDAR scan simulator in one include: sensors, scenes, simulate(), ground truth files.
#pragma once

#include "iilfm/sim/ground_truth_io.hpp"
#include "iilfm/sim/marker_texture.hpp"
#include "iilfm/sim/physics_request.hpp"
#include "iilfm/sim/scene.hpp"
#include "iilfm/sim/scene_file.hpp"
#include "iilfm/sim/scenes.hpp"
#include "iilfm/sim/sensor_models.hpp"
#include "iilfm/sim/simulate.hpp"
