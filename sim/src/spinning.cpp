// Velodyne-style spinning sensors: every ring fires once per azimuth column. The head turns
// clockwise seen from above (azimuth decreasing, as Velodynes do) and each sweep starts behind
// the sensor, so the seam between sweeps is not in front where scenes put their markers.
// All rings of a column share the column's firing time (the microsecond stagger is ignored).
#include <cmath>

#include "scan_pattern.hpp"

namespace iilfm::sim {
namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
}  // namespace

void spinning_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams) {
  const int columns = static_cast<int>(std::lround(360.0 / sensor.azimuth_step_deg));
  const int rings = static_cast<int>(sensor.ring_elevations_deg.size());
  const double sweep_s = 1.0 / sensor.frame_rate_hz;
  std::vector<double> cos_el(rings), sin_el(rings);
  for (int r = 0; r < rings; ++r) {
    cos_el[r] = std::cos(sensor.ring_elevations_deg[r] * kDegToRad);
    sin_el[r] = std::sin(sensor.ring_elevations_deg[r] * kDegToRad);
  }
  beams.resize(static_cast<std::size_t>(columns) * rings);
  std::size_t k = 0;
  for (int c = 0; c < columns; ++c) {
    const double azimuth = (180.0 - c * sensor.azimuth_step_deg) * kDegToRad;
    const double ca = std::cos(azimuth), sa = std::sin(azimuth);
    const double time = frame * sweep_s + sweep_s * c / columns;
    for (int r = 0; r < rings; ++r, ++k) {
      beams[k].direction = Vec3(cos_el[r] * ca, cos_el[r] * sa, sin_el[r]);
      beams[k].time = time;
      beams[k].ring = static_cast<std::uint16_t>(r);
    }
  }
}

}  // namespace iilfm::sim
