// One simulated scan: every beam of the sensor ray-cast into a scene, plus the ground truth.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "iilfm/sim/scene.hpp"
#include "iilfm/sim/sensor_models.hpp"
#include "iilfm/types.hpp"

namespace iilfm::sim {

struct SimOptions {
  Isometry3 T_world_lidar = Isometry3::Identity();  // the LiDAR's pose in the world
  int frames = 1;  // integrated frames (rosette: consecutive 0.1 s; spinning: repeated sweeps)
  std::uint64_t seed = 1;
  double range_sigma_m = -1;    // < 0: the sensor's default; 0 disables
  double intensity_sigma = -1;  // additive intensity noise, result clamped to >= 0; < 0: sensor's
  // Beam direction jitter: the range and intensity come from a jittered ray while the point is
  // reported along the nominal direction, as an encoder or beam-divergence error would.
  double angle_sigma_deg = 0;

  // Beam footprint: the returned intensity is the mean over a grid of sub-rays spread across the
  // sensor's divergence (a sub-ray that hits nothing adds 0), so a beam straddling a black-white
  // edge returns grey, as real mixed returns do. The range still comes from the beam's centre.
  bool footprint = false;
  int footprint_samples = 5;  // sub-rays along the footprint's longer axis (>= 1)
  // Probability that a return is lost when its whole footprint lies on black print (scaled by the
  // black fraction of the footprint): dark, absorbing ink returns too little light.
  double dark_dropout = 0;
  // How a return's intensity is formed. kReflectivity: the surface's reflectivity whatever the
  // range and angle, as sensors reporting calibrated reflectivity give it (Livox, Velodyne).
  // kRaw: the strength of the return, as a photon count (Ouster's `intensity`) falls off:
  // reflectivity x cos(incidence) x (raw_reference_m / range)^2, equal to the reflectivity
  // head-on at raw_reference_m (no near-field loss, no saturation). Noise is added after.
  // kSensor: what the sensor model reports (SensorModel::raw_intensity: the Ouster models' photon
  // count is raw, the others calibrated reflectivity on their own scale:
  // SensorModel::intensity_curve, Hesai's for the xt32).
  enum class IntensityModel {
    kSensor,
    kReflectivity,
    kRaw
  } intensity_model = IntensityModel::kSensor;
  double raw_reference_m = 10;
  double min_range_m = -1;  // < 0: the sensor's; returns closer than this are dropped
  // Fraction of beams written as invalid points, as drivers of organised clouds emit for lost
  // returns: NaN coordinates or (0, 0, 0), intensity 0.
  double invalid_fraction = 0;
  enum class Invalid { kNaN, kZero } invalid_as = Invalid::kNaN;

  // A moving sensor, for motion-distortion work: constant velocities from T_world_lidar at
  // time 0 (the start of frame 0). `linear_velocity` (m/s) is along the axes of the LiDAR frame
  // at time 0 and constant in the world; `angular_velocity` (rad/s) is about the LiDAR's own
  // axes. Pose at time t: R(t) = R0 Exp(w t), p(t) = p0 + R0 v t (lidar_pose_at). Each beam is
  // cast from the pose at its own time stamp and its point is written in the LiDAR frame at
  // that time, as a driver writes it, so the cloud is skewed; the ground truth keeps the pose
  // at time 0.
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
};

struct MarkerTruth {
  std::string family;
  int id = 0;
  double size_m = 0;
  Isometry3 T_world_marker = Isometry3::Identity(), T_lidar_marker = Isometry3::Identity();
  // Top-left, top-right, bottom-right, bottom-left of the outer black square.
  std::array<Vec3, 4> corners_world, corners_lidar;
  bool visible = false;  // all corners in the sensor's FoV and range, printed face towards it
  std::size_t points_on_marker = 0;  // returns that landed inside the outer black square
};

struct GroundTruth {
  std::string sensor;
  Isometry3 T_world_lidar = Isometry3::Identity();
  int frames = 1;
  std::uint64_t seed = 1;
  std::vector<MarkerTruth> markers;
  double range_sigma_m = 0;  // the sigma actually used
};

struct SimResult {
  PointCloud cloud;  // in the LiDAR frame; `time` always, `ring` for spinning sensors
  GroundTruth truth;
};

// Deterministic for a given seed. The range, intensity and angle noise of every beam is the same
// whatever the footprint, dropout and invalid-point options (those draw from a second stream).
// InputError for an unknown family, an id outside the family, a non-positive size, frames < 1, or
// options out of range (footprint_samples < 1, probabilities outside [0, 1]).
SimResult simulate(const Scene& scene, const SensorModel& sensor, const SimOptions& options);

// T_world_lidar at `time_s` seconds after the start of frame 0 under the options' velocities.
Isometry3 lidar_pose_at(const SimOptions& options, double time_s);

// The ground truth alone (no ray casting); simulate() fills points_on_marker on top of it.
GroundTruth ground_truth(const Scene& scene, const SensorModel& sensor, const SimOptions& options);

}  // namespace iilfm::sim
