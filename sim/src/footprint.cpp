// Beam divergence: the returned intensity is the average over the lit spot, which turns the hard
// black-white edges of a print into a ramp as wide as the spot.
#include "footprint.hpp"

#include <algorithm>
#include <cmath>

namespace iilfm::sim {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

// Centres of n equal slices of [-width/2, width/2].
std::vector<double> slice_centres(int n, double width) {
  std::vector<double> centres;
  for (int i = 0; i < n; ++i) centres.push_back(width * ((i + 0.5) / n - 0.5));
  return centres;
}

}  // namespace

BeamFootprint::BeamFootprint(const SensorModel& sensor, int samples) {
  const double across = sensor.divergence_h_deg * kDegToRad;
  const double up = sensor.divergence_v_deg * kDegToRad;
  const double longer = std::max(across, up);
  auto count = [&](double width) {
    if (longer <= 0) return 1;
    return std::max(1, static_cast<int>(std::lround(samples * width / longer)));
  };
  for (double a : slice_centres(count(across), across)) {
    for (double b : slice_centres(count(up), up)) offsets_.emplace_back(a, b);
  }
}

FootprintReturn BeamFootprint::cast(const SceneRaycaster& raycaster, const Vec3& origin,
                                    const Vec3& direction) const {
  // Across = the direction of growing azimuth (left), up = the direction of growing elevation.
  const Vec3 horizontal = Vec3::UnitZ().cross(direction);
  const Vec3 across = horizontal.norm() > 1e-9 ? horizontal.normalized() : Vec3::UnitY();
  const Vec3 up = direction.cross(across);
  FootprintReturn result;
  RayHit hit;
  for (const Vec2& o : offsets_) {
    const Vec3 sub = (direction + o.x() * across + o.y() * up).normalized();
    if (!raycaster.cast_from(origin, sub, &hit)) continue;
    result.intensity += hit.intensity;
    result.black_fraction += hit.on_black_print ? 1 : 0;
  }
  const double n = static_cast<double>(offsets_.size());
  result.intensity /= n;
  result.black_fraction /= n;
  return result;
}

}  // namespace iilfm::sim
