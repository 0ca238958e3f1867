// iilfm.simulate: the scan simulator of `iilfm sim`, with the same options and messages.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "bindings.hpp"
#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/sim/sim.hpp"

namespace iilfm::python {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

bool finite3(const std::optional<std::vector<double>>& v) {
  return v->size() == 3 && std::isfinite((*v)[0]) && std::isfinite((*v)[1]) &&
         std::isfinite((*v)[2]);
}

struct SimArgs {
  std::string scene = "tag-wall";
  std::optional<std::string> scene_file, sensor, family, out, map, truth;
  std::optional<int> frames, id;
  std::uint64_t seed = 1;
  std::optional<double> marker_size, distance, range_sigma, intensity_sigma, min_range;
  double angle_sigma = 0, dark_dropout = 0, invalid_fraction = 0;
  bool footprint = false;
  int footprint_samples = 5;
  std::string invalid_as = "nan", intensity_model = "sensor";
  std::optional<std::vector<double>> lidar_xyz, lidar_rpy;
};

sim::SceneSetup scene_setup(const SimArgs& a) {
  if (a.scene_file) {
    require(!a.family && !a.id && !a.marker_size && !a.distance,
            "family, id, marker_size and distance do not apply with scene_file");
    return sim::read_scene_yaml(*a.scene_file);
  }
  sim::SceneParams params;
  params.family = a.family;
  params.id = a.id;
  if (a.marker_size) {
    require(*a.marker_size > 0 && std::isfinite(*a.marker_size),
            "--marker-size must be a positive number of metres");
    params.marker_size_m = a.marker_size;
  }
  if (a.distance) {
    require(*a.distance > 0 && std::isfinite(*a.distance),
            "--distance must be a positive number of metres");
    params.distance_m = a.distance;
  }
  return sim::named_scene(a.scene, params);
}

py::dict truth_dict(const sim::GroundTruth& t) {
  py::dict d;
  d["sensor"] = t.sensor;
  d["frames"] = t.frames;
  d["seed"] = t.seed;
  d["range_sigma_m"] = t.range_sigma_m;
  d["T_world_lidar"] = to_numpy(t.T_world_lidar.matrix());
  py::list markers;
  for (const sim::MarkerTruth& m : t.markers) {
    py::dict md;
    md["family"] = m.family;
    md["id"] = m.id;
    md["size_m"] = m.size_m;
    md["visible"] = m.visible;
    md["points_on_marker"] = m.points_on_marker;
    Eigen::Matrix<double, 4, 3, Eigen::RowMajor> world, lidar;
    for (int k = 0; k < 4; ++k) {
      world.row(k) = m.corners_world[k].transpose();
      lidar.row(k) = m.corners_lidar[k].transpose();
    }
    md["corners_world"] = to_numpy(world);
    md["corners_lidar"] = to_numpy(lidar);
    md["T_world_marker"] = to_numpy(m.T_world_marker.matrix());
    md["T_lidar_marker"] = to_numpy(m.T_lidar_marker.matrix());
    markers.append(md);
  }
  d["markers"] = markers;
  return d;
}

py::tuple simulate(const SimArgs& a) {
  const sim::SceneSetup setup = scene_setup(a);
  const sim::SensorModel sensor = sim::sensor_model(a.sensor ? *a.sensor : setup.sensor);
  sim::SimOptions options;
  options.T_world_lidar = setup.T_world_lidar;
  if (a.lidar_xyz) {
    require(finite3(a.lidar_xyz), "--lidar-xyz needs three finite numbers");
    options.T_world_lidar.translation() =
        Vec3((*a.lidar_xyz)[0], (*a.lidar_xyz)[1], (*a.lidar_xyz)[2]);
  }
  if (a.lidar_rpy) {
    require(finite3(a.lidar_rpy), "--lidar-rpy needs three finite angles in degrees");
    const auto& r = *a.lidar_rpy;
    options.T_world_lidar.linear() = (Eigen::AngleAxisd(r[2] * kDegToRad, Vec3::UnitZ()) *
                                      Eigen::AngleAxisd(r[1] * kDegToRad, Vec3::UnitY()) *
                                      Eigen::AngleAxisd(r[0] * kDegToRad, Vec3::UnitX()))
                                         .toRotationMatrix();
  }
  options.frames = a.frames ? *a.frames : sim::default_frames(sensor);
  require(options.frames >= 1 && options.frames <= 100000, "--frames must be 1..100000");
  options.seed = a.seed;
  sim::PhysicsRequest physics;
  physics.range_sigma_m = a.range_sigma;
  physics.intensity_sigma = a.intensity_sigma;
  physics.min_range_m = a.min_range;
  physics.angle_sigma_deg = a.angle_sigma;
  physics.footprint = a.footprint;
  physics.footprint_samples = a.footprint_samples;
  physics.dark_dropout = a.dark_dropout;
  physics.invalid_fraction = a.invalid_fraction;
  physics.invalid_as = a.invalid_as;
  physics.intensity_model = a.intensity_model;
  sim::apply_physics(physics, options);

  sim::SimResult result;
  {
    py::gil_scoped_release release;
    result = sim::simulate(setup.scene, sensor, options);
    if (a.out) io::write_pcd(*a.out, result.cloud);
    if (a.truth) sim::write_ground_truth_json(*a.truth, result.truth);
    if (a.map) sim::write_marker_map_yaml(*a.map, setup.scene);
  }
  Cloud cloud;
  cloud.stats.points_in_file = cloud.stats.valid_points = result.cloud.size();
  *cloud.points = std::move(result.cloud);
  return py::make_tuple(std::move(cloud), truth_dict(result.truth));
}

}  // namespace

void register_simulate(py::module_& m) {
  m.def(
      "simulate",
      [](std::string scene, std::optional<std::filesystem::path> scene_file,
         std::optional<std::string> sensor, std::optional<int> frames, std::uint64_t seed,
         std::optional<std::string> family, std::optional<int> id,
         std::optional<double> marker_size, std::optional<double> distance,
         std::optional<double> range_sigma, std::optional<double> intensity_sigma,
         double angle_sigma, bool footprint, int footprint_samples, double dark_dropout,
         double invalid_fraction, std::string invalid_as, std::optional<double> min_range,
         std::optional<std::vector<double>> lidar_xyz, std::optional<std::vector<double>> lidar_rpy,
         std::optional<std::filesystem::path> out, std::optional<std::filesystem::path> map,
         std::optional<std::filesystem::path> truth, std::string intensity_model) {
        SimArgs a;
        a.scene = std::move(scene);
        auto text = [](const std::optional<std::filesystem::path>& p) {
          return p ? std::optional<std::string>(p->string()) : std::nullopt;
        };
        a.scene_file = text(scene_file);
        a.sensor = std::move(sensor);
        a.frames = frames;
        a.seed = seed;
        a.family = std::move(family);
        a.id = id;
        a.marker_size = marker_size;
        a.distance = distance;
        a.range_sigma = range_sigma;
        a.intensity_sigma = intensity_sigma;
        a.angle_sigma = angle_sigma;
        a.footprint = footprint;
        a.footprint_samples = footprint_samples;
        a.dark_dropout = dark_dropout;
        a.invalid_fraction = invalid_fraction;
        a.invalid_as = std::move(invalid_as);
        a.min_range = min_range;
        a.lidar_xyz = std::move(lidar_xyz);
        a.lidar_rpy = std::move(lidar_rpy);
        a.out = text(out);
        a.map = text(map);
        a.truth = text(truth);
        a.intensity_model = std::move(intensity_model);
        return simulate(a);
      },
      py::kw_only(), py::arg("scene") = "tag-wall", py::arg("scene_file") = py::none(),
      py::arg("sensor") = py::none(), py::arg("frames") = py::none(), py::arg("seed") = 1,
      py::arg("family") = py::none(), py::arg("id") = py::none(),
      py::arg("marker_size") = py::none(), py::arg("distance") = py::none(),
      py::arg("range_sigma") = py::none(), py::arg("intensity_sigma") = py::none(),
      py::arg("angle_sigma") = 0.0, py::arg("footprint") = false, py::arg("footprint_samples") = 5,
      py::arg("dark_dropout") = 0.0, py::arg("invalid_fraction") = 0.0,
      py::arg("invalid_as") = "nan", py::arg("min_range") = py::none(),
      py::arg("lidar_xyz") = py::none(), py::arg("lidar_rpy") = py::none(),
      py::arg("out") = py::none(), py::arg("map") = py::none(), py::arg("truth") = py::none(),
      py::arg("intensity_model") = "sensor",
      "Simulates a LiDAR scan of a scene, as `iilfm sim` does (same keywords with '-' as '_').\n"
      "Returns (cloud, truth): an iilfm.Cloud in the LiDAR frame and the ground truth as a dict\n"
      "(T_world_lidar and each marker's corners_world / corners_lidar (4, 3), T_lidar_marker).\n"
      "out=, map=, truth= also write the PCD, the scene's marker map YAML and the truth JSON.\n"
      "Deterministic for a given seed.");
}

}  // namespace iilfm::python
