// `iilfm sim`: simulates a LiDAR scan of a named scene and writes the cloud, its ground truth and
// the scene's marker map.
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/sim/sim.hpp"

namespace iilfm::cli {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

struct SimArgs {
  std::string sensor, out, truth, map, scene = "tag-wall", scene_file, family;
  int frames = 0, id = 0;
  std::uint64_t seed = 1;
  double range_sigma = -1, intensity_sigma = -1, angle_sigma = 0;
  double marker_size = 0, distance = 0;
  bool footprint = false;
  int footprint_samples = 5;
  double dark_dropout = 0, invalid_fraction = 0, min_range = -1;
  std::string invalid_as = "nan", intensity_model = "sensor";
  std::vector<double> lidar_xyz, lidar_rpy, velocity, angular_velocity;
  // Options whose absence means "the scene's default".
  CLI::Option *sensor_opt, *frames_opt, *range_sigma_opt, *intensity_sigma_opt, *min_range_opt,
      *family_opt, *id_opt, *size_opt, *distance_opt, *scene_opt;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

// Roll-pitch-yaw in degrees, extrinsic x-y-z (ARCHITECTURE.md): R = Rz(yaw) Ry(pitch) Rx(roll).
Mat3 rotation_from_rpy_deg(const std::vector<double>& rpy) {
  return (Eigen::AngleAxisd(rpy[2] * kDegToRad, Vec3::UnitZ()) *
          Eigen::AngleAxisd(rpy[1] * kDegToRad, Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy[0] * kDegToRad, Vec3::UnitX()))
      .toRotationMatrix();
}

bool all_finite(const std::vector<double>& values) {
  for (double v : values) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
  return text;
}

// The noise and physics flags; unset ones keep the sensor's defaults.
sim::PhysicsRequest physics_request(const SimArgs& a) {
  sim::PhysicsRequest r;
  if (a.range_sigma_opt->count()) r.range_sigma_m = a.range_sigma;
  if (a.intensity_sigma_opt->count()) r.intensity_sigma = a.intensity_sigma;
  if (a.min_range_opt->count()) r.min_range_m = a.min_range;
  r.angle_sigma_deg = a.angle_sigma;
  r.footprint = a.footprint;
  r.footprint_samples = a.footprint_samples;
  r.dark_dropout = a.dark_dropout;
  r.invalid_fraction = a.invalid_fraction;
  r.invalid_as = a.invalid_as;
  r.intensity_model = a.intensity_model;
  return r;
}

sim::SceneSetup scene_from_file(const SimArgs& a) {
  for (const CLI::Option* o : {a.scene_opt, a.family_opt, a.id_opt, a.size_opt, a.distance_opt}) {
    require(o->count() == 0, o->get_name() + " does not apply with --scene-file");
  }
  return sim::read_scene_yaml(a.scene_file);
}

sim::SceneSetup scene_by_name(const SimArgs& a) {
  sim::SceneParams params;
  if (a.family_opt->count()) params.family = a.family;
  if (a.id_opt->count()) params.id = a.id;
  if (a.size_opt->count()) {
    require(a.marker_size > 0 && std::isfinite(a.marker_size),
            "--marker-size must be a positive number of metres");
    params.marker_size_m = a.marker_size;
  }
  if (a.distance_opt->count()) {
    require(a.distance > 0 && std::isfinite(a.distance),
            "--distance must be a positive number of metres");
    params.distance_m = a.distance;
  }
  return sim::named_scene(a.scene, params);
}

int run_sim(const SimArgs& a) {
  const sim::SceneSetup setup = a.scene_file.empty() ? scene_by_name(a) : scene_from_file(a);
  const sim::SensorModel sensor =
      sim::sensor_model(a.sensor_opt->count() ? a.sensor : setup.sensor);

  sim::SimOptions options;
  options.T_world_lidar = setup.T_world_lidar;
  if (!a.lidar_xyz.empty()) {
    require(all_finite(a.lidar_xyz), "--lidar-xyz needs three finite numbers");
    options.T_world_lidar.translation() = Vec3(a.lidar_xyz[0], a.lidar_xyz[1], a.lidar_xyz[2]);
  }
  if (!a.lidar_rpy.empty()) {
    require(all_finite(a.lidar_rpy), "--lidar-rpy needs three finite angles in degrees");
    options.T_world_lidar.linear() = rotation_from_rpy_deg(a.lidar_rpy);
  }
  options.frames = a.frames_opt->count() ? a.frames : sim::default_frames(sensor);
  require(options.frames >= 1 && options.frames <= 100000, "--frames must be 1..100000");
  options.seed = a.seed;
  sim::apply_physics(physics_request(a), options);
  if (!a.velocity.empty()) {
    require(all_finite(a.velocity), "--velocity needs three finite numbers in m/s");
    options.linear_velocity = Vec3(a.velocity[0], a.velocity[1], a.velocity[2]);
  }
  if (!a.angular_velocity.empty()) {
    require(all_finite(a.angular_velocity),
            "--angular-velocity needs three finite numbers in deg/s");
    options.angular_velocity =
        Vec3(a.angular_velocity[0], a.angular_velocity[1], a.angular_velocity[2]) * kDegToRad;
  }

  const sim::SimResult result = sim::simulate(setup.scene, sensor, options);
  io::write_pcd(a.out, result.cloud);
  std::string written = a.out;
  if (!a.truth.empty()) {
    sim::write_ground_truth_json(a.truth, result.truth);
    written += ", " + a.truth;
  }
  if (!a.map.empty()) {
    sim::write_marker_map_yaml(a.map, setup.scene);
    written += ", " + a.map;
  }
  std::size_t visible = 0;
  for (const sim::MarkerTruth& m : result.truth.markers) visible += m.visible ? 1 : 0;
  std::cout << "iilfm sim: " << result.cloud.size() << " points (" << sensor.name << ", "
            << options.frames << " frame" << (options.frames == 1 ? "" : "s") << ", scene "
            << (a.scene_file.empty() ? a.scene : a.scene_file) << ", " << visible << "/"
            << result.truth.markers.size() << " markers visible) -> " << written << "\n";
  return 0;
}

}  // namespace

Runner register_sim_command(CLI::App& app) {
  auto args = std::make_shared<SimArgs>();
  CLI::App* sub = app.add_subcommand("sim", "Simulate a LiDAR scan of markers on a wall");
  SimArgs& a = *args;
  a.sensor_opt = sub->add_option(
      "--sensor", a.sensor,
      "Simulated sensor: " + joined(sim::sensor_model_names()) + " (default: the scene's)");
  sub->add_option("--out", a.out, "Output point cloud (binary PCD)")->required();
  sub->add_option("--truth", a.truth, "Write the ground truth JSON here");
  sub->add_option("--map", a.map, "Write the scene's marker map YAML here");
  a.scene_opt = sub->add_option("--scene", a.scene, "Scene: " + joined(sim::named_scene_names()))
                    ->capture_default_str();
  sub->add_option("--scene-file", a.scene_file,
                  "Scene YAML file (docs/simulator.md), e.g. data/scenes/room.yaml");
  a.frames_opt = sub->add_option("--frames", a.frames,
                                 "Integrated frames of 0.1 s (default 40 rosette, 1 spinning)");
  sub->add_option("--seed", a.seed, "Noise seed")->capture_default_str();
  a.range_sigma_opt = sub->add_option("--range-sigma", a.range_sigma,
                                      "Range noise sigma in metres (default: the sensor's)");
  a.intensity_sigma_opt = sub->add_option("--intensity-sigma", a.intensity_sigma,
                                          "Intensity noise sigma (default: the sensor's, 4)");
  sub->add_option("--angle-sigma", a.angle_sigma, "Beam direction jitter sigma in degrees")
      ->capture_default_str();
  sub->add_flag("--footprint", a.footprint,
                "Beam divergence: intensity averaged over the footprint (grey mixed edges)");
  sub->add_option("--footprint-samples", a.footprint_samples,
                  "Sub-rays along the footprint's longer axis")
      ->capture_default_str();
  sub->add_option("--dark-dropout", a.dark_dropout,
                  "Probability that a return on black print is lost")
      ->capture_default_str();
  sub->add_option("--invalid-fraction", a.invalid_fraction,
                  "Share of beams written as invalid points, as drivers emit")
      ->capture_default_str();
  sub->add_option("--invalid-as", a.invalid_as, "Invalid points as nan or zero coordinates")
      ->capture_default_str();
  sub->add_option(
         "--intensity-model", a.intensity_model,
         "sensor (the model's own: raw for Ouster, reflectivity otherwise, on Hesai's scale "
         "for xt32 and pandar40p), "
         "reflectivity (calibrated, as Livox/Velodyne) or raw (x cos(incidence) x "
         "(10 m / range)^2, as Ouster's photon count)")
      ->capture_default_str();
  a.min_range_opt = sub->add_option("--min-range", a.min_range,
                                    "Minimum range in metres (default: the sensor's)");
  a.family_opt =
      sub->add_option("--family", a.family,
                      "Marker family, e.g. apriltag:tag36h11 or aruco:DICT_4X4_50 (default: "
                      "the scene's)");
  a.id_opt = sub->add_option("--id", a.id, "Marker id (grid: id of the top-left marker)");
  a.size_opt = sub->add_option("--marker-size", a.marker_size,
                               "Edge of the outer black square in metres (tag-wall: 0.172)");
  a.distance_opt = sub->add_option("--distance", a.distance,
                                   "LiDAR to wall in metres (tag-wall 2, grid 3.5, paper-grid 4; "
                                   "ccw10m: to the marker, 10)");
  sub->add_option("--lidar-xyz", a.lidar_xyz, "LiDAR position in the world (overrides --distance)")
      ->expected(3);
  sub->add_option("--lidar-rpy", a.lidar_rpy, "LiDAR roll pitch yaw in degrees (extrinsic x-y-z)")
      ->expected(3);
  sub->add_option("--velocity", a.velocity,
                  "Sensor velocity in m/s along the LiDAR axes at the scan start (skews the cloud)")
      ->expected(3);
  sub->add_option("--angular-velocity", a.angular_velocity,
                  "Sensor turn rate in deg/s about its own x y z axes")
      ->expected(3);
  return [args]() { return run_sim(*args); };
}

}  // namespace iilfm::cli
