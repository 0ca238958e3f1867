// Picks the scan pattern generator for a sensor.
#include "scan_pattern.hpp"

namespace iilfm::sim {

void scan_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams) {
  switch (sensor.pattern) {
    case ScanPattern::kRosette:
      rosette_frame(sensor, frame, beams);
      return;
    case ScanPattern::kSpinning:
      spinning_frame(sensor, frame, beams);
      return;
    case ScanPattern::kBand:
      band_frame(sensor, frame, beams);
      return;
  }
}

}  // namespace iilfm::sim
