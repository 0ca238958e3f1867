// The scan loop: generate each frame's beams, cast them, add noise, keep the returns in range.
#include "iilfm/sim/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "footprint.hpp"
#include "iilfm/error.hpp"
#include "normal_sampler.hpp"
#include "raycast.hpp"
#include "scan_pattern.hpp"

namespace iilfm::sim {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

void check_inputs(const Scene& scene, const SensorModel& sensor, const SimOptions& options) {
  if (options.frames < 1) {
    throw InputError("simulated frames must be at least 1, got " + std::to_string(options.frames));
  }
  if (!(sensor.points_per_second > 0) || !(sensor.frame_rate_hz > 0)) {
    throw InputError("sensor '" + sensor.name + "' needs a positive point and frame rate");
  }
  if (sensor.pattern == ScanPattern::kRosette &&
      (!(sensor.fov_deg > 0 && sensor.fov_deg < 180) ||
       !(sensor.fov_v_deg >= 0 && sensor.fov_v_deg < 180))) {
    throw InputError("rosette sensor '" + sensor.name + "' needs a field of view in (0, 180) deg");
  }
  if (sensor.pattern == ScanPattern::kSpinning &&
      (sensor.ring_elevations_deg.empty() || !(sensor.azimuth_step_deg > 0))) {
    throw InputError("spinning sensor '" + sensor.name + "' needs rings and an azimuth step");
  }
  if (sensor.pattern == ScanPattern::kBand &&
      (sensor.band_beams < 1 ||
       !(sensor.band_low_deg >= -90 && sensor.band_low_deg < sensor.band_high_deg &&
         sensor.band_high_deg <= 90))) {
    throw InputError("band sensor '" + sensor.name +
                     "' needs at least one beam and a band within -90..90 deg");
  }
  auto probability = [](double p) { return p >= 0 && p <= 1; };
  if (options.footprint && options.footprint_samples < 1) {
    throw InputError("footprint needs at least one sub-ray, got " +
                     std::to_string(options.footprint_samples));
  }
  if (options.intensity_model != SimOptions::IntensityModel::kReflectivity &&
      !(options.raw_reference_m > 0 && std::isfinite(options.raw_reference_m))) {
    throw InputError("raw intensity needs a positive reference range");
  }
  if (!probability(options.dark_dropout) || !probability(options.invalid_fraction)) {
    throw InputError("dark dropout and invalid fraction must be probabilities in [0, 1]");
  }
  if (!options.linear_velocity.allFinite() || !options.angular_velocity.allFinite()) {
    throw InputError("sensor velocities must be finite");
  }
  for (const MarkerSpec& m : scene.markers) {
    if (!(m.size_m > 0)) {
      throw InputError("marker " + m.family + "/" + std::to_string(m.id) +
                       " needs a positive size, got " + std::to_string(m.size_m));
    }
  }
}

// Whether a LiDAR-frame point lies inside the sensor's angular field of view.
bool in_field_of_view(const SensorModel& sensor, const Vec3& p) {
  const double n = p.norm();
  if (n == 0) return false;
  if (sensor.pattern == ScanPattern::kRosette) {
    // Angle from the axis split along y and z as the rosette lays its offsets out; inside the
    // (possibly elliptical) cone when the offsets fall within the ellipse of half-angles.
    const double rho = std::acos(std::clamp(p.x() / n, -1.0, 1.0));
    const double lateral = std::hypot(p.y(), p.z());
    if (lateral == 0) return p.x() > 0;  // on the axis, ahead or behind
    const double half_h = sensor.fov_deg / 2 * kDegToRad;
    const double half_v =
        (sensor.fov_v_deg > 0 ? sensor.fov_v_deg : sensor.fov_deg) / 2 * kDegToRad;
    const double u = rho * p.y() / lateral / half_h, v = rho * p.z() / lateral / half_v;
    return u * u + v * v <= 1 + 1e-12;
  }
  const double elevation = std::asin(std::clamp(p.z() / n, -1.0, 1.0)) / kDegToRad;
  if (sensor.pattern == ScanPattern::kBand)
    return elevation >= sensor.band_low_deg && elevation <= sensor.band_high_deg;
  const auto [lowest, highest] =
      std::minmax_element(sensor.ring_elevations_deg.begin(), sensor.ring_elevations_deg.end());
  return elevation >= *lowest && elevation <= *highest;
}

// The direction `d` turned by a small random angle (two independent components of sigma).
Vec3 jittered(const Vec3& d, double sigma_rad, NormalSampler& normal) {
  const Vec3 helper = std::abs(d.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
  const Vec3 e1 = d.cross(helper).normalized();
  const Vec3 e2 = d.cross(e1);
  const double a = sigma_rad * normal.next(), b = sigma_rad * normal.next();
  return (d + a * e1 + b * e2).normalized();
}

// The sensor with the options' overrides applied.
SensorModel effective_sensor(const SensorModel& sensor, const SimOptions& options) {
  SensorModel s = sensor;
  if (options.min_range_m >= 0) s.min_range_m = options.min_range_m;
  return s;
}

// The LiDAR at `time_s` in the LiDAR frame at time 0 (constant velocities, SimOptions).
Isometry3 start_from_now(const SimOptions& options, double time_s) {
  Isometry3 T = Isometry3::Identity();
  T.translation() = options.linear_velocity * time_s;
  const double angle = options.angular_velocity.norm() * time_s;
  if (angle != 0) {
    T.linear() = Eigen::AngleAxisd(angle, options.angular_velocity.normalized()).toRotationMatrix();
  }
  return T;
}

}  // namespace

Isometry3 lidar_pose_at(const SimOptions& options, double time_s) {
  return options.T_world_lidar * start_from_now(options, time_s);
}

GroundTruth ground_truth(const Scene& scene, const SensorModel& nominal,
                         const SimOptions& options) {
  const SensorModel sensor = effective_sensor(nominal, options);
  GroundTruth truth;
  truth.sensor = sensor.name;
  truth.T_world_lidar = options.T_world_lidar;
  truth.frames = options.frames;
  truth.seed = options.seed;
  truth.range_sigma_m = options.range_sigma_m < 0 ? sensor.range_sigma_m : options.range_sigma_m;
  const Isometry3 T_lidar_world = options.T_world_lidar.inverse();
  for (const MarkerSpec& m : scene.markers) {
    MarkerTruth t;
    t.family = m.family;
    t.id = m.id;
    t.size_m = m.size_m;
    t.T_world_marker = m.T_world_marker;
    t.T_lidar_marker = T_lidar_world * m.T_world_marker;
    t.corners_world = marker_corners_world(m);
    bool visible = true;
    for (int i = 0; i < 4; ++i) {
      t.corners_lidar[i] = T_lidar_world * t.corners_world[i];
      const double range = t.corners_lidar[i].norm();
      visible = visible && range >= sensor.min_range_m && range <= sensor.max_range_m &&
                in_field_of_view(sensor, t.corners_lidar[i]);
    }
    // The printed face points at the LiDAR when the marker's z axis points back at the origin.
    const Vec3 normal = t.T_lidar_marker.linear().col(2);
    t.visible = visible && normal.dot(-t.T_lidar_marker.translation()) > 0;
    truth.markers.push_back(t);
  }
  return truth;
}

SimResult simulate(const Scene& scene, const SensorModel& nominal, const SimOptions& options) {
  check_inputs(scene, nominal, options);
  const SensorModel sensor = effective_sensor(nominal, options);
  SimResult result;
  result.truth = ground_truth(scene, sensor, options);
  const double range_sigma = result.truth.range_sigma_m;
  const double intensity_sigma =
      options.intensity_sigma < 0 ? sensor.intensity_sigma : options.intensity_sigma;
  const double angle_sigma = options.angle_sigma_deg * kDegToRad;
  const bool spinning = sensor.pattern == ScanPattern::kSpinning;
  const bool moving = !options.linear_velocity.isZero(0) || !options.angular_velocity.isZero(0);

  const bool raw =
      options.intensity_model == SimOptions::IntensityModel::kRaw ||
      (options.intensity_model == SimOptions::IntensityModel::kSensor && sensor.raw_intensity);
  const SceneRaycaster raycaster(scene, options.T_world_lidar.inverse(),
                                 raw ? options.raw_reference_m : 0.0);
  std::optional<BeamFootprint> footprint;
  if (options.footprint) footprint.emplace(sensor, options.footprint_samples);
  NormalSampler normal(options.seed);
  UniformSampler uniform(options.seed);
  PointCloud& cloud = result.cloud;
  cloud.reserve(static_cast<std::size_t>(points_per_frame(sensor)) * options.frames, spinning,
                true);
  // The sensor's own scale for calibrated returns; the raw and reflectivity models as they are.
  const bool own_scale = !raw && options.intensity_model == SimOptions::IntensityModel::kSensor;
  const auto reported = [&](double intensity) {
    return own_scale ? reported_intensity(sensor, intensity) : std::max(0.0, intensity);
  };
  auto emit = [&](const Vec3& p, double intensity, const Beam& beam) {
    cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()),
                    static_cast<float>(intensity));
    cloud.time.push_back(beam.time);
    if (spinning) cloud.ring.push_back(beam.ring);
  };
  const Vec3 invalid_point = options.invalid_as == SimOptions::Invalid::kNaN
                                 ? Vec3::Constant(std::numeric_limits<double>::quiet_NaN())
                                 : Vec3::Zero();

  std::vector<Beam> beams;
  RayHit hit;
  for (int frame = 0; frame < options.frames; ++frame) {
    scan_frame(sensor, frame, beams);
    for (const Beam& beam : beams) {
      // Every beam draws the same numbers whether or not it returns, so a seed means the same
      // noise per beam whatever the scene.
      const double range_noise = range_sigma * normal.next();
      const double intensity_noise = intensity_sigma * normal.next();
      Vec3 cast_direction =
          angle_sigma > 0 ? jittered(beam.direction, angle_sigma, normal) : beam.direction;
      // A moving sensor casts from where it is at the beam's time; the scene stays in the
      // frame of time 0, so the ray moves into that frame instead.
      Vec3 origin = Vec3::Zero();
      if (moving) {
        const Isometry3 T = start_from_now(options, beam.time);
        origin = T.translation();
        cast_direction = T.linear() * cast_direction;
      }
      const bool invalid =
          options.invalid_fraction > 0 && uniform.next() < options.invalid_fraction;
      const double dropout_draw = options.dark_dropout > 0 ? uniform.next() : 1.0;
      if (invalid) {
        emit(invalid_point, 0, beam);
        continue;
      }
      if (!raycaster.cast_from(origin, cast_direction, &hit)) continue;
      const double range = hit.range + range_noise;
      if (range < sensor.min_range_m || range > sensor.max_range_m) continue;
      double intensity = hit.intensity;
      double black_fraction = hit.on_black_print ? 1 : 0;
      if (footprint) {
        const FootprintReturn spot = footprint->cast(raycaster, origin, cast_direction);
        intensity = spot.intensity;
        black_fraction = spot.black_fraction;
      }
      if (dropout_draw < options.dark_dropout * black_fraction) continue;
      emit(range * beam.direction, reported(intensity + intensity_noise), beam);
      if (hit.in_black_square) ++result.truth.markers[hit.marker].points_on_marker;
    }
  }
  return result;
}

}  // namespace iilfm::sim
