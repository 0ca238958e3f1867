// Internal: a beam's footprint as a grid of sub-rays across the sensor's divergence, and the
// intensity a detector integrating over it would report.
#pragma once

#include <vector>

#include "iilfm/sim/sensor_models.hpp"
#include "iilfm/types.hpp"
#include "raycast.hpp"

namespace iilfm::sim {

struct FootprintReturn {
  double intensity = 0;       // mean over the sub-rays, 0 for each that hits nothing
  double black_fraction = 0;  // share of sub-rays that land on black print
};

class BeamFootprint {
 public:
  // `samples` sub-rays along the longer divergence axis, proportionally fewer (at least one)
  // along the shorter; a uniform grid over the full divergence angle.
  BeamFootprint(const SensorModel& sensor, int samples);

  FootprintReturn cast(const SceneRaycaster& raycaster, const Vec3& direction) const {
    return cast(raycaster, Vec3::Zero(), direction);
  }
  // From `origin` (LiDAR frame), as a moving sensor casts.
  FootprintReturn cast(const SceneRaycaster& raycaster, const Vec3& origin,
                       const Vec3& direction) const;

  std::size_t sub_rays() const { return offsets_.size(); }

 private:
  std::vector<Vec2> offsets_;  // (across, up) in radians from the beam's centre
};

}  // namespace iilfm::sim
