// `iilfm sensors`: the sensor presets.
#include <cstdio>

#include "commands.hpp"
#include "iilfm/sensor.hpp"

namespace iilfm::cli {

Runner register_sensors_command(CLI::App& app) {
  app.add_subcommand("sensors", "List the sensor presets");
  return [] {
    std::printf("%-10s %9s %9s %-22s %9s  %s\n", "preset", "res_h_deg", "res_v_deg",
                "fov (h x v deg)", "threshold", "sensor");
    for (const SensorPreset& p : sensor_presets()) {
      char fov[64];
      std::snprintf(fov, sizeof fov, "%g..%g x %g..%g", p.fov_h_min_deg, p.fov_h_max_deg,
                    p.fov_v_min_deg, p.fov_v_max_deg);
      std::printf("%-10s %9g %9g %-22s %9g  %s\n", p.name.c_str(), p.res_h_deg, p.res_v_deg, fov,
                  p.threshold, p.description.c_str());
    }
    return 0;
  };
}

}  // namespace iilfm::cli
