#include "iilfm/sensor.hpp"

#include "iilfm/error.hpp"

namespace iilfm {

const std::vector<SensorPreset>& sensor_presets() {
  // Thresholds are in each sensor's own intensity units. Livox and Velodyne report calibrated
  // diffuse reflectivity (0-100 %, higher for retro-reflectors): black toner returns about 5-10,
  // white paper and light paint 60-90, so 40 splits print from any light surface. Hesai
  // Pandar64's scale is offset (black print 60-85, white 110-145 in the bundled real scans).
  // Tune with --threshold for other materials.
  static const std::vector<SensorPreset> presets = {
      {"mid40", "Livox Mid-40 (38.4 deg circular FoV, non-repetitive)", 0.05, 0.05, -19.2, 19.2,
       -19.2, 19.2, 40},
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
