// Livox Mid-40 rosette as a Risley-prism pair: two wedge prisms spinning in opposite directions
// each deflect the beam by a = fov/4, so their sum sweeps petals that all pass through the axis
// and reach fov/2 at their tips. An irrational speed ratio makes the petals never repeat, so the
// covered fraction of the field of view keeps growing with integration time.
#include <cmath>

#include "scan_pattern.hpp"

namespace iilfm::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

// Prism speeds in revolutions per second (about 7300 and 4500 rpm: 20 petals a frame). The second
// turns the other way at 1/golden-ratio of the first: the most irrational ratio there is, so the
// petals drift around the axis without ever closing, and 40 frames come within a few per cent of
// the coverage of 400k uniformly random directions.
constexpr double kPrism1Hz = 121.6;
constexpr double kGolden = 1.6180339887498949;
constexpr double kPrism2Hz = -kPrism1Hz / kGolden;

}  // namespace

void rosette_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams) {
  const int n = points_per_frame(sensor);
  // An elliptical cone (Avia) scales the prism sum along each axis: the petals keep their
  // non-repeating drift, stretched to the vertical extent.
  const double a = sensor.fov_deg / 4.0 * kDegToRad;
  const double a_v = (sensor.fov_v_deg > 0 ? sensor.fov_v_deg : sensor.fov_deg) / 4.0 * kDegToRad;
  const double w1 = 2 * kPi * kPrism1Hz, w2 = 2 * kPi * kPrism2Hz;
  const double dt = 1.0 / sensor.points_per_second;
  const std::int64_t first = static_cast<std::int64_t>(frame) * n;
  beams.resize(n);
  for (int k = 0; k < n; ++k) {
    const double t = static_cast<double>(first + k) * dt;
    // Angular offset from the axis: first component towards +y (left), second towards +z (up).
    const double oy = a * (std::cos(w1 * t) + std::cos(w2 * t));
    const double oz = a_v * (std::sin(w1 * t) + std::sin(w2 * t));
    const double rho = std::hypot(oy, oz);  // angle from the axis
    Beam& b = beams[k];
    if (rho < 1e-12) {
      b.direction = Vec3::UnitX();
    } else {
      const double s = std::sin(rho) / rho;
      b.direction = Vec3(std::cos(rho), oy * s, oz * s);
    }
    b.time = t;
    b.ring = 0;
  }
}

}  // namespace iilfm::sim
