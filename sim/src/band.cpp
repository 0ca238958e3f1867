// A band scanner (Livox Mid-360-like): the head turns once a frame through 360 deg, anticlockwise
// seen from above, starting behind the sensor so the frames' seam is not in front. Its beams run
// up and down the elevation band in a triangle wave, spread evenly over its period, so each beam
// draws steep zigzags across the band. The wave runs 38.618... periods a turn: the fraction is
// the golden ratio's, so each frame's zigzags fall between the earlier frames' ones and the band
// fills in as frames are integrated, never repeating. Each beam's wave runs 1.31 % faster than the
// one before, so the beams drift across each other instead of drawing one rigid lattice, which
// left a fifth of the 0.5 deg cells empty at 10 frames where random directions leave a tenth.
#include <cmath>

#include "scan_pattern.hpp"

namespace iilfm::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kWavesPerTurn = 38.0 + 0.6180339887498949;
constexpr double kBeamRateStep = 0.0131;

// 0 at phase 0, 1 at phase 1/2, back to 0 at phase 1.
double triangle(double phase) {
  const double f = phase - std::floor(phase);
  return f < 0.5 ? 2 * f : 2 - 2 * f;
}

}  // namespace

void band_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams) {
  const int n = points_per_frame(sensor);
  const int beam_count = sensor.band_beams;
  const double dt = 1.0 / sensor.points_per_second;
  const double low = sensor.band_low_deg * kDegToRad;
  const double span = (sensor.band_high_deg - sensor.band_low_deg) * kDegToRad;
  const std::int64_t first = static_cast<std::int64_t>(frame) * n;
  beams.resize(n);
  // The beams fire in turn: point k belongs to beam k mod beam_count.
  for (int k = 0; k < n; ++k) {
    const std::int64_t index = first + k;
    const double t = static_cast<double>(index) * dt;
    const double turns = t * sensor.frame_rate_hz;
    const double azimuth = (turns - std::floor(turns)) * 2 * kPi - kPi;
    const int beam = static_cast<int>(index % beam_count);
    const double waves = turns * kWavesPerTurn * (1 + kBeamRateStep * beam);
    const double elevation = low + span * triangle(waves + static_cast<double>(beam) / beam_count);
    Beam& b = beams[k];
    b.direction = Vec3(std::cos(elevation) * std::cos(azimuth),
                       std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    b.time = t;
    b.ring = 0;
  }
}

}  // namespace iilfm::sim
