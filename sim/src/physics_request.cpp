#include "iilfm/sim/physics_request.hpp"

#include <cmath>

#include "iilfm/error.hpp"

namespace iilfm::sim {

namespace {
void require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}
bool probability(double p) { return p >= 0 && p <= 1; }
}  // namespace

void apply_physics(const PhysicsRequest& r, SimOptions& options) {
  if (r.range_sigma_m) {
    require(*r.range_sigma_m >= 0 && std::isfinite(*r.range_sigma_m),
            "--range-sigma must be a non-negative number of metres");
    options.range_sigma_m = *r.range_sigma_m;
  }
  if (r.intensity_sigma) {
    require(*r.intensity_sigma >= 0 && std::isfinite(*r.intensity_sigma),
            "--intensity-sigma must be non-negative");
    options.intensity_sigma = *r.intensity_sigma;
  }
  require(r.angle_sigma_deg >= 0 && std::isfinite(r.angle_sigma_deg),
          "--angle-sigma must be a non-negative number of degrees");
  options.angle_sigma_deg = r.angle_sigma_deg;
  options.footprint = r.footprint;
  require(r.footprint_samples >= 1 && r.footprint_samples <= 50,
          "--footprint-samples must be 1..50");
  options.footprint_samples = r.footprint_samples;
  require(probability(r.dark_dropout), "--dark-dropout must be a probability in [0, 1]");
  options.dark_dropout = r.dark_dropout;
  require(probability(r.invalid_fraction), "--invalid-fraction must be a fraction in [0, 1]");
  options.invalid_fraction = r.invalid_fraction;
  require(r.invalid_as == "nan" || r.invalid_as == "zero", "--invalid-as must be nan or zero");
  options.invalid_as =
      r.invalid_as == "nan" ? SimOptions::Invalid::kNaN : SimOptions::Invalid::kZero;
  require(r.intensity_model == "sensor" || r.intensity_model == "reflectivity" ||
              r.intensity_model == "raw",
          "--intensity-model must be sensor, reflectivity or raw");
  options.intensity_model = r.intensity_model == "raw" ? SimOptions::IntensityModel::kRaw
                            : r.intensity_model == "reflectivity"
                                ? SimOptions::IntensityModel::kReflectivity
                                : SimOptions::IntensityModel::kSensor;
  if (r.min_range_m) {
    require(*r.min_range_m >= 0 && std::isfinite(*r.min_range_m),
            "--min-range must be a non-negative number of metres");
    options.min_range_m = *r.min_range_m;
  }
}

}  // namespace iilfm::sim
