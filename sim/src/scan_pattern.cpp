// Picks the scan pattern generator for a sensor.
#include "scan_pattern.hpp"

namespace iilfm::sim {

void scan_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams) {
  if (sensor.pattern == ScanPattern::kRosette) {
    rosette_frame(sensor, frame, beams);
  } else {
    spinning_frame(sensor, frame, beams);
  }
}

}  // namespace iilfm::sim
