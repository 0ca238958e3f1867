#include "iilfm/sensor.hpp"

#include "iilfm/error.hpp"

namespace iilfm {

const std::vector<SensorPreset>& sensor_presets() {
  // Thresholds sit between the returns of black toner and white office paper on each sensor's
  // intensity scale (0-255 for all of these); tune them with --threshold for other materials.
  static const std::vector<SensorPreset> presets = {
      {"mid40", "Livox Mid-40 (38.4 deg circular FoV, non-repetitive)", 0.05, 0.05, -19.2, 19.2,
       -19.2, 19.2, 60},
      {"vlp16", "Velodyne VLP-16 (16 rings, 2 deg, 10 Hz)", 0.2, 2.0, -180, 180, -15, 15, 40},
      {"vlp32c", "Velodyne VLP-32C (32 non-uniform rings, 10 Hz)", 0.2, 0.333, -180, 180, -25, 15,
       40},
      {"ultrapuck", "Velodyne ULTRA Puck (32 non-uniform rings, 10 Hz)", 0.2, 0.333, -180, 180, -25,
       15, 40},
      {"pandar64", "Hesai Pandar64 (64 rings, 0.167 deg in the dense band, 10 Hz)", 0.2, 0.167,
       -180, 180, -25, 15, 100},
  };
  return presets;
}

const SensorPreset& find_sensor_preset(const std::string& name) {
  std::string known;
  for (const SensorPreset& preset : sensor_presets()) {
    if (preset.name == name) return preset;
    known += (known.empty() ? "" : ", ") + preset.name;
  }
  throw InputError("unknown sensor preset '" + name + "' (known: " + known + ")");
}

}  // namespace iilfm
