// The simulator's noise and physics as a user asks for them (`iilfm sim` flags, Python keywords),
// checked once with one message per flag.
#pragma once

#include <optional>
#include <string>

#include "iilfm/sim/simulate.hpp"

namespace iilfm::sim {

struct PhysicsRequest {
  std::optional<double> range_sigma_m, intensity_sigma, min_range_m;  // unset: the sensor's
  double angle_sigma_deg = 0;
  bool footprint = false;
  int footprint_samples = 5;
  double dark_dropout = 0, invalid_fraction = 0;
  std::string invalid_as = "nan";                // "nan" or "zero"
  std::string intensity_model = "reflectivity";  // or "raw" (SimOptions::IntensityModel)
};

// Checks `request` and copies it into `options`; InputError naming the flag otherwise.
void apply_physics(const PhysicsRequest& request, SimOptions& options);

}  // namespace iilfm::sim
