// Internal: the beams a sensor fires in one frame, in the LiDAR frame (x forward, y left, z up).
#pragma once

#include <cstdint>
#include <vector>

#include "iilfm/sim/sensor_models.hpp"
#include "iilfm/types.hpp"

namespace iilfm::sim {

struct Beam {
  Vec3 direction;  // unit vector
  double time;     // seconds since the start of frame 0
  std::uint16_t ring;
};

// Replaces `beams` with frame `frame` of a rosette sensor: beam k fires at (frame * n + k) / pps.
void rosette_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams);

// Replaces `beams` with sweep `frame` of a spinning sensor, column by column, rings bottom-up.
void spinning_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams);

// Replaces `beams` with frame `frame` of a band sensor: beam k fires at (frame * n + k) / pps.
void band_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams);

// Dispatches on sensor.pattern.
void scan_frame(const SensorModel& sensor, int frame, std::vector<Beam>& beams);

}  // namespace iilfm::sim
