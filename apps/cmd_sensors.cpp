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
}  // namespace

Runner register_sensors_command(CLI::App& app) {
  app.add_subcommand("sensors", "List the sensor presets");
  return [] {
    std::printf("%-12s %9s %9s %5s %-26s %9s %6s  %s\n", "preset", "res_h_deg", "res_v_deg",
                "rings", "fov (h x v deg)", "threshold", "frames", "sensor");
    for (const SensorPreset& p : sensor_presets()) {
      char fov[64];
      std::snprintf(fov, sizeof fov, "%g..%g x %g..%g", p.fov_h_min_deg, p.fov_h_max_deg,
                    p.fov_v_min_deg, p.fov_v_max_deg);
      const std::string threshold = p.threshold ? format_number(*p.threshold) : "otsu";
      const std::string rings = p.rings > 0 ? std::to_string(p.rings) : "-";
      std::printf("%-12s %9.4g %9.4g %5s %-26s %9s %6d  %s\n", p.name.c_str(), p.res_h_deg,
                  p.res_v_deg, rings.c_str(), fov, threshold.c_str(), p.frames,
                  p.description.c_str());
    }
    return 0;
  };
}

}  // namespace iilfm::cli
