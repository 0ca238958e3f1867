// Simulating a case and running the pipeline on it.
#include "iilfm/eval/case.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "iilfm/error.hpp"
#include "iilfm/pose.hpp"
#include "iilfm/resolution.hpp"
#include "iilfm/sensor.hpp"

namespace iilfm::eval {
namespace {

// Drivers of organised clouds emit NaN or (0, 0, 0) for lost returns; the file readers drop
// those, so the evaluation does too before handing the cloud to the pipeline.
void drop_invalid_points(PointCloud& cloud) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const float x = cloud.x[i], y = cloud.y[i], z = cloud.z[i];
    const bool finite = std::isfinite(x) && std::isfinite(y) && std::isfinite(z) &&
                        std::isfinite(cloud.intensity[i]);
    if (!finite || (x == 0 && y == 0 && z == 0)) continue;
    cloud.x[kept] = x;
    cloud.y[kept] = y;
    cloud.z[kept] = z;
    cloud.intensity[kept] = cloud.intensity[i];
    if (cloud.has_time()) cloud.time[kept] = cloud.time[i];
    if (cloud.has_ring()) cloud.ring[kept] = cloud.ring[i];
    ++kept;
  }
  cloud.x.resize(kept);
  cloud.y.resize(kept);
  cloud.z.resize(kept);
  cloud.intensity.resize(kept);
  if (cloud.has_time()) cloud.time.resize(kept);
  if (cloud.has_ring()) cloud.ring.resize(kept);
}

// Smallest gap between neighbouring rings: the row height that gives every ring its own row.
double closest_ring_spacing_deg(const sim::SensorModel& sensor) {
  std::vector<double> rings = sensor.ring_elevations_deg;
  std::sort(rings.begin(), rings.end());
  double closest = 180;
  for (std::size_t i = 1; i < rings.size(); ++i)
    closest = std::min(closest, rings[i] - rings[i - 1]);
  return closest;
}

}  // namespace

const char* lift_name(LiftMethod lift) { return lift == LiftMethod::kPaper ? "paper" : "plane"; }

MarkerMap map_of(const sim::Scene& scene) {
  MarkerMap map;
  for (const sim::MarkerSpec& m : scene.markers) {
    MapMarker mm;
    mm.family = m.family;
    mm.id = m.id;
    mm.corners_world = sim::marker_corners_world(m);
    map.add(mm);
  }
  return map;
}

namespace {
CaseSpec scene_spec(const char* scene, const std::string& sensor, double distance_m) {
  CaseSpec spec;
  spec.scene = scene;
  spec.sensor = sensor;
  spec.scene_params.distance_m = distance_m;
  return spec;
}
}  // namespace

CaseSpec tag_wall_spec(const std::string& sensor, double distance_m, double marker_size_m) {
  CaseSpec spec = scene_spec("tag-wall", sensor, distance_m);
  spec.scene_params.marker_size_m = marker_size_m;
  return spec;
}

CaseSpec grid_spec(const std::string& sensor, const std::string& family, double distance_m) {
  CaseSpec spec = scene_spec("grid", sensor, distance_m);
  spec.scene_params.family = family;
  return spec;
}

SimulatedCase simulate_case(const CaseSpec& spec, std::uint64_t seed) {
  SimulatedCase c;
  c.setup = sim::named_scene(spec.scene, spec.scene_params);
  c.sensor = sim::sensor_model(spec.sensor.empty() ? c.setup.sensor : spec.sensor);
  if (spec.on_column_grid) c.sensor.ring_azimuth_offsets_deg.clear();
  sim::SimOptions options = spec.physics;
  options.T_world_lidar = c.setup.T_world_lidar;
  options.T_world_lidar.linear() =
      c.setup.T_world_lidar.linear() * rotation_from_rpy_deg(spec.lidar_rpy_deg);
  if (spec.jitter_px > 0) {
    // Its own random stream, so that the scan's noise stays that of the seed.
    std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + 0x5EED);
    std::uniform_real_distribution<double> phase(-0.5, 0.5);
    const PipelineOptions pipeline = pipeline_options_for(c, LiftMethod::kPlane);
    const double yaw = phase(rng) * spec.jitter_px * pipeline.projection.res_h_deg;
    const double pitch = phase(rng) * spec.jitter_px * pipeline.projection.res_v_deg;
    options.T_world_lidar.linear() =
        options.T_world_lidar.linear() * rotation_from_rpy_deg(Vec3(0, pitch, yaw));
  }
  options.frames = spec.frames > 0 ? spec.frames : sim::default_frames(c.sensor);
  options.seed = seed;
  c.scan = sim::simulate(c.setup.scene, c.sensor, options);
  drop_invalid_points(c.scan.cloud);
  return c;
}

PipelineOptions pipeline_options_for(const SimulatedCase& c, LiftMethod lift) {
  PipelineOptions options;
  const auto& presets = sensor_presets();
  const auto preset = std::find_if(presets.begin(), presets.end(),
                                   [&](const SensorPreset& p) { return p.name == c.sensor.name; });
  if (preset != presets.end()) {
    apply_sensor_preset(*preset, options);
    // As `iilfm detect --sensor` does: the columns of the scan's mode (the simulated OS1-128
    // runs 2048 columns, its preset assumes 1024).
    if (const std::optional<double> step = mode_column_step(*preset, c.scan.cloud))
      options.projection.res_h_deg = *step;
  } else if (c.sensor.pattern == sim::ScanPattern::kSpinning) {
    options.projection.res_h_deg = c.sensor.azimuth_step_deg;
    options.projection.res_v_deg = closest_ring_spacing_deg(c.sensor);
    options.preprocess.threshold = 40;  // between black print (10) and white paper (120)
  } else {
    throw InputError("no image resolution known for simulated sensor '" + c.sensor.name + "'");
  }
  std::vector<std::string> families;
  for (const sim::MarkerSpec& m : c.setup.scene.markers) {
    if (std::find(families.begin(), families.end(), m.family) == families.end()) {
      families.push_back(m.family);
    }
  }
  options.families = families;
  options.map = map_of(c.setup.scene);
  options.lift = lift;
  // The paper's method reports its four lifted corners as they are.
  options.fit_known_size = lift != LiftMethod::kPaper;
  return options;
}

CaseScore run_case(const SimulatedCase& c, LiftMethod lift, const PipelineTweaks& tweaks) {
  PipelineOptions options = pipeline_options_for(c, lift);
  options.edge_refine = tweaks.edge_refine;
  options.pose.weight_corners = tweaks.weight_corners;
  options.pose.refine = tweaks.pose_refine;
  options.ring_decode = tweaks.ring_decode;
  options.ring_candidates = tweaks.ring_candidates;
  options.detector.apriltag.search_regions = tweaks.search_regions;
  options.detector.aruco.search_regions = tweaks.search_regions;
  options.detector.apriltag.decode_gray = tweaks.gray_decode;
  options.projection.column_offsets = tweaks.column_offsets;
  Pipeline pipeline(options);
  return score_frame(pipeline.process(c.scan.cloud), c.scan.truth);
}

}  // namespace iilfm::eval
