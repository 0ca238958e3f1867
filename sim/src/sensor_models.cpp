// Published figures of the sensors the simulator imitates (maker data sheets).
#include "iilfm/sim/sensor_models.hpp"

#include <cmath>

#include "iilfm/error.hpp"

namespace iilfm::sim {
namespace {

constexpr double kSpinningAzimuthStepDeg = 0.2;  // 600 rpm = 10 Hz sweeps
constexpr double kSpinningFrameRateHz = 10;

// A spinning sensor fires every ring once per azimuth column.
double spinning_points_per_second(std::size_t rings) {
  const double columns = std::round(360.0 / kSpinningAzimuthStepDeg);
  return static_cast<double>(rings) * columns * kSpinningFrameRateHz;
}

}  // namespace

SensorModel mid40() {
  SensorModel s;
  s.name = "mid40";
  s.pattern = ScanPattern::kRosette;
  s.points_per_second = 100000;
  s.frame_rate_hz = 10;
  s.range_sigma_m = 0.02;
  s.min_range_m = 1.0;
  s.max_range_m = 260;
  s.fov_deg = 38.4;
  return s;
}

SensorModel vlp16() {
  SensorModel s;
  s.name = "vlp16";
  s.pattern = ScanPattern::kSpinning;
  for (int ring = 0; ring < 16; ++ring) s.ring_elevations_deg.push_back(-15.0 + 2.0 * ring);
  s.azimuth_step_deg = kSpinningAzimuthStepDeg;
  s.frame_rate_hz = kSpinningFrameRateHz;
  s.points_per_second = spinning_points_per_second(s.ring_elevations_deg.size());
  s.range_sigma_m = 0.03;
  s.min_range_m = 0.5;
  s.max_range_m = 100;
  return s;
}

SensorModel ultra_puck() {
  SensorModel s;
  s.name = "ultrapuck";
  s.pattern = ScanPattern::kSpinning;
  // VLP-32C / ULTRA Puck laser elevations sorted from the lowest beam up (denser near horizon).
  s.ring_elevations_deg = {-25,    -15.639, -11.31, -8.843, -7.254, -6.148, -5.333, -4.667,
                           -4,     -3.667,  -3.333, -3,     -2.667, -2.333, -2,     -1.667,
                           -1.333, -1,      -0.667, -0.333, 0,      0.333,  0.667,  1,
                           1.333,  1.667,   2.333,  3.333,  4.667,  7,      10.333, 15};
  s.azimuth_step_deg = kSpinningAzimuthStepDeg;
  s.frame_rate_hz = kSpinningFrameRateHz;
  s.points_per_second = spinning_points_per_second(s.ring_elevations_deg.size());
  s.range_sigma_m = 0.03;
  s.min_range_m = 0.5;
  s.max_range_m = 200;
  return s;
}

std::vector<std::string> sensor_model_names() { return {"mid40", "vlp16", "ultrapuck"}; }

SensorModel sensor_model(const std::string& name) {
  if (name == "mid40") return mid40();
  if (name == "vlp16") return vlp16();
  if (name == "ultrapuck") return ultra_puck();
  std::string known;
  for (const std::string& n : sensor_model_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown simulated sensor '" + name + "' (known: " + known + ")");
}

int points_per_frame(const SensorModel& sensor) {
  return static_cast<int>(std::lround(sensor.points_per_second / sensor.frame_rate_hz));
}

}  // namespace iilfm::sim
