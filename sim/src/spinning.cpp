// Velodyne-style spinning sensors: every ring fires once per azimuth column. The head turns
// clockwise seen from above (azimuth decreasing, as Velodynes do) and each sweep starts behind
// the sensor, so the seam between sweeps is not in front where scenes put their markers.
// Each ring points SensorModel::ring_azimuth_offsets_deg clockwise of its column; all rings of a
// column share the column's firing time (microseconds apart on the real sensors).
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
  std::vector<double> cos_el(rings), sin_el(rings), cos_lag(rings, 1.0), sin_lag(rings, 0.0);
  for (int r = 0; r < rings; ++r) {
    cos_el[r] = std::cos(sensor.ring_elevations_deg[r] * kDegToRad);
    sin_el[r] = std::sin(sensor.ring_elevations_deg[r] * kDegToRad);
    if (static_cast<std::size_t>(r) < sensor.ring_azimuth_offsets_deg.size()) {
      const double lag = sensor.ring_azimuth_offsets_deg[static_cast<std::size_t>(r)] * kDegToRad;
      cos_lag[r] = std::cos(lag);
      sin_lag[r] = std::sin(lag);
    }
  }
  beams.resize(static_cast<std::size_t>(columns) * rings);
  std::size_t k = 0;
  for (int c = 0; c < columns; ++c) {
    const double azimuth = (180.0 - c * sensor.azimuth_step_deg) * kDegToRad;
    const double ca = std::cos(azimuth), sa = std::sin(azimuth);
    const double time = frame * sweep_s + sweep_s * c / columns;
    for (int r = 0; r < rings; ++r, ++k) {
      // The ring's azimuth, `azimuth` less its lag.
      const double cr = ca * cos_lag[r] + sa * sin_lag[r], sr = sa * cos_lag[r] - ca * sin_lag[r];
      beams[k].direction = Vec3(cos_el[r] * cr, cos_el[r] * sr, sin_el[r]);
      beams[k].time = time;
      beams[k].ring = static_cast<std::uint16_t>(r);
    }
  }
}

}  // namespace iilfm::sim
