#include "iilfm/eval/intensity_study.hpp"

#include <cstdio>
#include <random>

#include "iilfm/option_names.hpp"
#include "iilfm/pose.hpp"
#include "iilfm/sim/physics_request.hpp"

namespace iilfm::eval {

std::vector<IntensityVariant> default_intensity_variants() {
  return {{"preset", "", ""},
          {"fixed 40", "40", "none"},
          {"fixed 1000", "1000", "none"},
          {"fixed 40 + range", "40", "range"},
          {"fixed 40 + range-incidence", "40", "range-incidence"},
          {"otsu", "otsu", "none"},
          {"otsu + range", "otsu", "range"},
          {"otsu + range-incidence", "otsu", "range-incidence"},
          {"local", "local", "none"},
          {"local + range", "local", "range"}};
}

namespace {

PipelineOptions variant_options(const SimulatedCase& c, const IntensityVariant& v) {
  PipelineOptions options = pipeline_options_for(c, LiftMethod::kPlane);
  // In the CLI's order and with its meaning: "local" keeps the preset's (or, normalised, Otsu's)
  // threshold for flat regions.
  set_intensity_normalisation(v.normalise, options);
  set_threshold(v.threshold, options);
  return options;
}

// The scene of `spec` with, when near_m > 0, a board facing the LiDAR near_m away carrying marker
// id 1, beside the line of sight to the tag-wall marker (45 deg off for a spinning sensor, at the
// edge of a rosette's field of view).
SimulatedCase simulate_scene(const CaseSpec& spec, double near_m, std::uint64_t seed) {
  SimulatedCase c;
  c.setup = sim::named_scene(spec.scene, spec.scene_params);
  c.sensor = sim::sensor_model(spec.sensor);
  if (near_m > 0) {
    const double size = *spec.scene_params.marker_size_m, printed = size * 1.3;
    double azimuth = M_PI / 4;
    if (c.sensor.pattern == sim::ScanPattern::kRosette)
      azimuth = c.sensor.fov_deg / 2 * M_PI / 180 - std::atan(printed / 2 / near_m) - 0.02;
    const Vec3 lidar = c.setup.T_world_lidar.translation();
    const Vec3 centre = lidar + near_m * Vec3(std::cos(azimuth), std::sin(azimuth), 0);
    const sim::Wall board =
        sim::upright_wall(centre, azimuth * 180 / M_PI + 180, printed, printed, 60);
    c.setup.scene.walls.push_back(board);
    c.setup.scene.markers.push_back(
        sim::marker_on_wall(board, c.setup.scene.markers.at(0).family, 1, size, 0, 0));
  }
  sim::SimOptions options = spec.physics;
  options.T_world_lidar = c.setup.T_world_lidar;
  options.T_world_lidar.linear() =
      c.setup.T_world_lidar.linear() * rotation_from_rpy_deg(spec.lidar_rpy_deg);
  options.frames = sim::default_frames(c.sensor);
  options.seed = seed;
  c.scan = sim::simulate(c.setup.scene, c.sensor, options);
  return c;
}

// Whether the marker with this id was found with its own id.
bool found_id(const FrameResult& r, int id) {
  for (const MarkerResult& m : r.markers)
    if (m.detection.id == id) return true;
  return false;
}

}  // namespace

std::vector<IntensityResult> intensity_study(const IntensityQuery& query) {
  std::vector<IntensityResult> results;
  for (const IntensityVariant& v : query.variants) results.push_back({v, {}, {}, {}, 0, 0});
  sim::PhysicsRequest physics;
  physics.footprint = query.footprint;
  physics.intensity_model = query.intensity_model;
  for (double distance : query.distances) {
    CaseSpec spec = tag_wall_spec(query.sensor, distance, query.marker_size_m);
    sim::apply_physics(physics, spec.physics);
    std::vector<int> found(query.variants.size(), 0), near(found), both(found);
    for (int seed = 1; seed <= query.seeds; ++seed) {
      std::mt19937 rng(static_cast<std::uint32_t>(seed));
      std::uniform_real_distribution<double> tilt(-1.0, 1.0);
      spec.lidar_rpy_deg = Vec3(0, tilt(rng), 2 * tilt(rng));
      const SimulatedCase c = simulate_scene(spec, query.near_m, static_cast<std::uint64_t>(seed));
      // The same scene without its markers: every detection there is a false positive.
      SimulatedCase empty = c;
      empty.setup.scene.markers.clear();
      sim::SimOptions options = spec.physics;
      options.T_world_lidar = c.scan.truth.T_world_lidar;
      options.frames = c.scan.truth.frames;
      options.seed = static_cast<std::uint64_t>(seed);
      empty.scan = sim::simulate(empty.setup.scene, empty.sensor, options);
      for (std::size_t k = 0; k < query.variants.size(); ++k) {
        Pipeline pipeline(variant_options(c, query.variants[k]));
        const FrameResult& r = pipeline.process(c.scan.cloud);
        const bool far = found_id(r, 0), close = found_id(r, 1);
        const CaseScore score = score_frame(r, c.scan.truth);
        found[k] += far ? 1 : 0;
        near[k] += close ? 1 : 0;
        both[k] += far && close ? 1 : 0;
        results[k].false_positives += score.false_positives + score.wrong_ids;
        results[k].empty_scene_detections +=
            static_cast<int>(pipeline.process(empty.scan.cloud).markers.size());
      }
    }
    for (std::size_t k = 0; k < query.variants.size(); ++k) {
      results[k].found.emplace_back(distance, found[k]);
      results[k].found_near.push_back(near[k]);
      results[k].found_both.push_back(both[k]);
    }
  }
  return results;
}

std::string intensity_table_markdown(const IntensityQuery& query,
                                     const std::vector<IntensityResult>& results) {
  char text[160];
  std::snprintf(text, sizeof text, "%s, %.3g m marker, %s intensity, %d seeds",
                query.sensor.c_str(), query.marker_size_m, query.intensity_model.c_str(),
                query.seeds);
  std::string out = text;
  if (query.near_m > 0) {
    std::snprintf(text, sizeof text,
                  "; a second marker %g m away in every scan: cells read far / near / both",
                  query.near_m);
    out += text;
  }
  out += "\n\n";
  out += "| settings |";
  std::string rule = "|---|";
  for (double d : query.distances) {
    std::snprintf(text, sizeof text, " %g m |", d);
    out += text;
    rule += "---|";
  }
  out += " false positives | on the empty scene |\n" + rule + "---|---|\n";
  for (const IntensityResult& r : results) {
    out += "| " + r.variant.name + " |";
    for (std::size_t i = 0; i < r.found.size(); ++i) {
      out += " " + std::to_string(r.found[i].second);
      if (query.near_m > 0)
        out += " / " + std::to_string(r.found_near[i]) + " / " + std::to_string(r.found_both[i]);
      out += " |";
    }
    out += " " + std::to_string(r.false_positives) + " | " +
           std::to_string(r.empty_scene_detections) + " |\n";
  }
  return out;
}

}  // namespace iilfm::eval
