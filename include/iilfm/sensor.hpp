// Sensor presets: the angular resolution, field of view and default intensity threshold of the
// LiDARs iilfm knows by name (`--sensor`). Values and their sources are listed in docs/sensors.md.
#pragma once

#include <string>
#include <vector>

namespace iilfm {

struct SensorPreset {
  std::string name;         // lower-case CLI name, e.g. "mid40"
  std::string description;  // maker and model
  double res_h_deg = 0;     // horizontal (azimuth) angular resolution used for the image
  double res_v_deg = 0;     // vertical (elevation) angular resolution used for the image
  // Field of view. Spinning sensors cover 360 deg in azimuth; Livox cones are given as a box.
  double fov_h_min_deg = 0, fov_h_max_deg = 0;
  double fov_v_min_deg = 0, fov_v_max_deg = 0;
  double threshold = 0;  // default naive threshold, in the sensor's own intensity units
};

// All presets, in the order `iilfm sensors` lists them.
const std::vector<SensorPreset>& sensor_presets();

// The preset with this name; InputError naming the known presets otherwise.
const SensorPreset& find_sensor_preset(const std::string& name);

}  // namespace iilfm
