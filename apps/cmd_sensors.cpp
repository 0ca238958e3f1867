// `iilfm sensors`: the sensor presets.
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "iilfm/sensor.hpp"

namespace iilfm::cli {

namespace {

std::string format_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// The threshold as the pipeline applies it: the fixed value, and "+local" when a frame it finds
// nothing in is thresholded locally and detected again.
std::string threshold_of(const SensorPreset& p) {
  if (!p.threshold) return "otsu";
  return format_number(*p.threshold) + (p.retry_local_threshold ? "+local" : "");
}

}  // namespace

Runner register_sensors_command(CLI::App& app) {
  app.add_subcommand("sensors", "List the sensor presets");
  return [] {
    std::printf("%-12s %9s %9s %5s %-30s %-15s %9s %6s  %s\n", "preset", "res_h_deg", "res_v_deg",
                "rings", "fov (h x v deg)", "intensity", "threshold", "frames", "sensor");
    for (const SensorPreset& p : sensor_presets()) {
      char fov[64];
      std::snprintf(fov, sizeof fov, "%g..%g x %g..%g", p.fov_h_min_deg, p.fov_h_max_deg,
                    p.fov_v_min_deg, p.fov_v_max_deg);
      const std::string rings = p.rings > 0 ? std::to_string(p.rings) : "-";
      std::printf("%-12s %9.4g %9.4g %5s %-30s %-15s %9s %6d  %s\n", p.name.c_str(), p.res_h_deg,
                  p.res_v_deg, rings.c_str(), fov, to_string(p.normalise), threshold_of(p).c_str(),
                  p.frames, p.description.c_str());
    }
    std::printf(
        "\nintensity: normalisation for range (and incidence) before thresholding; none = as "
        "reported.\nthreshold: a fixed value that finds no marker is retried at Otsu's threshold "
        "when that lies\nfar from it; +local: else with the local threshold (docs/sensors.md).\n");
    return 0;
  };
}

}  // namespace iilfm::cli
