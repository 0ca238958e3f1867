#include "iilfm/sensor.hpp"

#include "iilfm/error.hpp"

namespace iilfm {

namespace {

SensorPreset livox(std::string name, std::string description, double res_deg, double h_min,
                   double h_max, double v_min, double v_max, int frames) {
  SensorPreset preset{std::move(name),
                      std::move(description),
                      ScanKind::kNonRepetitive,
                      0,
                      res_deg,
                      res_deg,
                      h_min,
                      h_max,
                      v_min,
                      v_max,
                      40.0,
                      frames,
                      IntensityNormalisation::kNone};
  preset.retry_local_threshold = true;
  return preset;
}

SensorPreset spinning(std::string name, std::string description, int rings, double res_h_deg,
                      double finest_ring_spacing_deg, double v_min, double v_max,
                      std::optional<double> threshold) {
  return {std::move(name),
          std::move(description),
          ScanKind::kSpinning,
          rings,
          res_h_deg,
          finest_ring_spacing_deg,
          -180,
          180,
          v_min,
          v_max,
          threshold,
          1,
          IntensityNormalisation::kNone};
}

// Ouster's `intensity` field (the one the readers take) is the return's photon count, which falls
// with range and incidence: normalised, with Otsu's threshold (docs/sensors.md, measured with
// `iilfm eval --suite intensity`).
SensorPreset ouster(std::string name, std::string description, int rings, double res_h_deg,
                    double ring_spacing_deg, double v_min, double v_max) {
  SensorPreset p = spinning(std::move(name), std::move(description), rings, res_h_deg,
                            ring_spacing_deg, v_min, v_max, std::nullopt);
  p.normalise = IntensityNormalisation::kRangeIncidence;
  return p;
}

}  // namespace

const std::vector<SensorPreset>& sensor_presets() {
  // Thresholds are in each sensor's own intensity units. Livox and Velodyne report calibrated
  // diffuse reflectivity (0-100 %, higher for retro-reflectors): black toner returns about 5-10,
  // white paper and light paint 60-90, so 40 splits print from any light surface. Hesai's scale is
  // offset (black print 60-85, white 110-145 in the bundled real Pandar64 scans). Ouster's and
  // RoboSense's default fields are not a fixed reflectivity scale: Otsu's threshold.
  // Livox image resolutions suit about one second of integration (docs/sensors.md).
  constexpr double kOuster1024 = 360.0 / 1024;
  static const std::vector<SensorPreset> presets = {
      livox("mid40", "Livox Mid-40 (38.4 deg circular FoV, non-repetitive, 100k pts/s)", 0.05,
            -19.2, 19.2, -19.2, 19.2, 60),
      livox("mid70", "Livox Mid-70 (70.4 deg circular FoV, non-repetitive, 100k pts/s)", 0.1, -35.2,
            35.2, -35.2, 35.2, 60),
      livox("avia", "Livox Avia (70.4 x 77.2 deg, non-repetitive, 240k pts/s)", 0.1, -35.2, 35.2,
            -38.6, 38.6, 20),
      livox("horizon", "Livox Horizon (81.7 x 25.1 deg, non-repetitive, 240k pts/s)", 0.1, -40.85,
            40.85, -12.55, 12.55, 20),
      livox("hap", "Livox HAP (120 x 25 deg, 452k pts/s)", 0.1, -60, 60, -12.5, 12.5, 10),
      livox("mid360", "Livox Mid-360 (360 x 59 deg, -7..52 deg, 200k pts/s)", 0.2, -180, 180, -7,
            52, 10),
      spinning("vlp16", "Velodyne VLP-16 (16 rings, 2 deg, 10 Hz)", 16, 0.2, 2.0, -15, 15, 40.0),
      spinning("vlp16-hires", "Velodyne VLP-16 Hi-Res (16 rings, 1.33 deg, 10 Hz)", 16, 0.2, 1.33,
               -10, 10, 40.0),
      spinning("vlp32c", "Velodyne VLP-32C (32 non-uniform rings, 0.33 deg finest, 10 Hz)", 32, 0.2,
               0.333, -25, 15, 40.0),
      spinning("ultrapuck", "Velodyne ULTRA Puck (32 non-uniform rings, 0.33 deg finest, 10 Hz)",
               32, 0.2, 0.333, -25, 15, 40.0),
      spinning("hdl32e", "Velodyne HDL-32E (32 rings, 1.33 deg, 10 Hz)", 32, 0.16, 1.33, -30.67,
               10.67, 40.0),
      // The manual's 64 equal subdivisions of 26.9 deg (0.427 deg; it rounds them to 0.4).
      spinning("hdl64e", "Velodyne HDL-64E (64 rings, about 0.43 deg, 10 Hz)", 64, 0.17, 26.9 / 63,
               -24.9, 2, 40.0),
      ouster("os0-32", "Ouster OS0-32 (32 rings over 90 deg, 1024 columns)", 32, kOuster1024,
             90.0 / 31, -45, 45),
      ouster("os0-64", "Ouster OS0-64 (64 rings over 90 deg, 1024 columns)", 64, kOuster1024,
             90.0 / 63, -45, 45),
      ouster("os0-128", "Ouster OS0-128 (128 rings over 90 deg, 1024 columns)", 128, kOuster1024,
             90.0 / 127, -45, 45),
      ouster("os1-32", "Ouster OS1-32 (32 rings over 45 deg, 1024 columns)", 32, kOuster1024,
             45.0 / 31, -22.5, 22.5),
      ouster("os1-64", "Ouster OS1-64 (64 rings over 45 deg, 1024 columns)", 64, kOuster1024,
             45.0 / 63, -22.5, 22.5),
      ouster("os1-128", "Ouster OS1-128 (128 rings over 45 deg, 1024 columns)", 128, kOuster1024,
             45.0 / 127, -22.5, 22.5),
      ouster("os2-32", "Ouster OS2-32 (32 rings over 22.5 deg, 1024 columns)", 32, kOuster1024,
             22.5 / 31, -11.25, 11.25),
      ouster("os2-64", "Ouster OS2-64 (64 rings over 22.5 deg, 1024 columns)", 64, kOuster1024,
             22.5 / 63, -11.25, 11.25),
      ouster("os2-128", "Ouster OS2-128 (128 rings over 22.5 deg, 1024 columns)", 128, kOuster1024,
             22.5 / 127, -11.25, 11.25),
      spinning("pandar40p", "Hesai Pandar40P (40 non-uniform rings, 0.33 deg finest, 10 Hz)", 40,
               0.2, 0.33, -25, 15, 100.0),
      spinning("pandar64", "Hesai Pandar64 (64 rings, 0.167 deg in the dense band, 10 Hz)", 64, 0.2,
               0.167, -25, 15, 100.0),
      spinning("xt32", "Hesai PandarXT-32 (32 rings, 1 deg, 10 Hz)", 32, 0.18, 1.0, -16, 15, 100.0),
      spinning("qt64", "Hesai PandarQT64 (64 rings over 104.2 deg, 10 Hz)", 64, 0.6, 1.45, -52.1,
               52.1, 100.0),
      spinning("rs16", "RoboSense RS-LiDAR-16 (16 rings, 2 deg, 10 Hz)", 16, 0.2, 2.0, -15, 15,
               std::nullopt),
      spinning("rs32", "RoboSense RS-LiDAR-32 (32 non-uniform rings, 0.33 deg finest, 10 Hz)", 32,
               0.2, 0.33, -25, 15, std::nullopt),
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
