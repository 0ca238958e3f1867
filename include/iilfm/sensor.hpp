// Sensor presets: the angular resolution, field of view, ring layout, default intensity threshold
// and integration of the LiDARs iilfm knows by name (`--sensor`). Values and their sources are
// listed in docs/sensors.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "iilfm/intensity_normalisation.hpp"

namespace iilfm {

enum class ScanKind {
  kNonRepetitive,  // Livox: a rosette or similar pattern whose coverage grows with integration
  kSpinning,       // rings of lasers: one image row per ring
};

struct SensorPreset {
  std::string name;         // lower-case CLI name, e.g. "mid40"
  std::string description;  // maker and model
  ScanKind kind = ScanKind::kSpinning;
  int rings = 0;         // laser channels of a spinning LiDAR (0 for Livox)
  double res_h_deg = 0;  // horizontal (azimuth) angular resolution used for the image
  double res_v_deg = 0;  // vertical: finest ring spacing (spinning) or image rows (Livox)
  // Field of view. Spinning sensors cover 360 deg in azimuth; Livox cones are given as a box.
  double fov_h_min_deg = 0, fov_h_max_deg = 0;
  double fov_v_min_deg = 0, fov_v_max_deg = 0;
  // Default naive threshold in the sensor's own intensity units; unset = Otsu's threshold, for
  // sensors whose intensity scale is not a calibrated reflectivity.
  std::optional<double> threshold;
  int frames = 1;  // frames to integrate for a usable image (`--frames` for sequences)
  // Intensity normalisation for sensors whose intensity falls with range (docs/sensors.md).
  IntensityNormalisation normalise = IntensityNormalisation::kNone;
  // PipelineOptions::retry_with_local_threshold: the Livox presets.
  bool retry_local_threshold = false;
};

// All presets, in the order `iilfm sensors` lists them.
const std::vector<SensorPreset>& sensor_presets();

// The preset with this name; InputError naming the known presets otherwise.
const SensorPreset& find_sensor_preset(const std::string& name);

}  // namespace iilfm
