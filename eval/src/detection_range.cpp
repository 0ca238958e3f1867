#include "iilfm/eval/detection_range.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "iilfm/sensor.hpp"
#include "iilfm/sim/sensor_models.hpp"

namespace iilfm::eval {

const char* settings_name(RangeSettings settings) {
  return settings == RangeSettings::kPaper ? "paper" : "iilfm";
}

PipelineOptions range_pipeline_options(const SimulatedCase& c, RangeSettings settings) {
  PipelineOptions options = pipeline_options_for(c, LiftMethod::kPlane);
  if (settings == RangeSettings::kPaper) {
    options.projection.rows = RowLayout::kUniform;
    options.preprocess.fill_holes = false;
    options.preprocess.hole_class_block = 0;
    options.preprocess.square_pixels = false;
    options.min_samples_per_cell = 0;
    options.detector.apriltag.decode_gray = false;  // the paper's AprilTag reads the binary image
    options.retry_with_otsu = false;                // one naive threshold
    options.retry_with_local_threshold = false;
    options.max_square_error = 0;  // every detection, square or not
  }
  return options;
}

double aim_pitch_deg(const std::string& sensor) {
  const sim::SensorModel model = sim::sensor_model(sensor);
  // A band looking up (Mid-360, -7..+52 deg) is tilted down to its middle, as rings looking down.
  if (model.pattern == sim::ScanPattern::kBand)
    return std::round((model.band_low_deg + model.band_high_deg) / 2);
  std::vector<double> rings = model.ring_elevations_deg;
  if (rings.size() < 2) return 0;
  std::sort(rings.begin(), rings.end());
  double min_gap = rings.back() - rings.front(), max_gap = 0;
  for (std::size_t i = 1; i < rings.size(); ++i) {
    min_gap = std::min(min_gap, rings[i] - rings[i - 1]);
    max_gap = std::max(max_gap, rings[i] - rings[i - 1]);
  }
  // Rings packed unevenly are packed where their makers expect targets: around the horizon.
  if (max_gap > 1.05 * min_gap) return 0;
  return std::round((rings.front() + rings.back()) / 2);
}

std::vector<RangeResult> detection_range(const RangeQuery& query,
                                         const std::vector<RangeSettings>& settings) {
  std::vector<RangeResult> results;
  for (RangeSettings s : settings) results.push_back({query, s, 0, 0, {}, 0});
  // A walk ends after two failures in a row once the marker was found, or after eight before (a
  // large marker may not fit the field of view up close).
  std::vector<int> failures_in_a_row(settings.size(), 0);
  std::vector<bool> seen(settings.size(), false);
  // A sensor whose field looks down (HDL-32E, HDL-64E) is tilted up so the level marker sits in
  // the middle of its rings, not clipped by its top ring.
  const double aim_pitch = aim_pitch_deg(query.sensor);
  auto done = [&](std::size_t k) { return failures_in_a_row[k] >= (seen[k] ? 2 : 8); };
  for (double distance : query.distances) {
    CaseSpec spec = tag_wall_spec(query.sensor, distance, query.marker_size_m);
    spec.scene_params.family = query.family;
    spec.physics.footprint = query.footprint;
    // The sensor's own intensity (SimOptions::IntensityModel::kSensor): raw for the Ouster
    // models, whose presets normalise it.
    std::vector<int> found(settings.size(), 0);
    bool any_running = false;
    for (std::size_t k = 0; k < settings.size(); ++k) any_running |= !done(k);
    if (!any_running) break;
    for (int seed = 1; seed <= query.seeds; ++seed) {
      // Where the rings cross the marker decides what a spinning LiDAR sees of it: each seed
      // tilts and turns the LiDAR a little so the seeds sample that phase, not only the noise.
      std::mt19937 rng(static_cast<std::uint32_t>(seed));
      std::uniform_real_distribution<double> tilt(-1.0, 1.0);
      spec.lidar_rpy_deg = Vec3(0, aim_pitch + tilt(rng), 2 * tilt(rng));
      const SimulatedCase c = simulate_case(spec, static_cast<std::uint64_t>(seed));
      for (std::size_t k = 0; k < settings.size(); ++k) {
        if (done(k)) continue;
        PipelineOptions options = range_pipeline_options(c, settings[k]);
        if (settings[k] == RangeSettings::kIilfm) {
          options.ring_decode = query.ring_decode;
          options.ring_candidates = query.ring_candidates;
          options.detector.apriltag.decode_gray = query.gray_decode;
        }
        if (!query.map) options.map.reset();
        options.detector.apriltag.search_regions = query.search_regions;
        options.detector.aruco.search_regions = query.search_regions;
        Pipeline pipeline(options);
        const CaseScore score = score_frame(pipeline.process(c.scan.cloud), c.scan.truth);
        found[k] += score.detected > 0 ? 1 : 0;
        results[k].false_positives += score.false_positives + score.wrong_ids;
      }
    }
    for (std::size_t k = 0; k < settings.size(); ++k) {
      if (done(k)) continue;
      results[k].found.emplace_back(distance, found[k]);
      if (found[k] >= query.required) {
        if (!seen[k]) results[k].min_distance_m = distance;
        results[k].max_distance_m = distance;
        failures_in_a_row[k] = 0;
        seen[k] = true;
      } else {
        ++failures_in_a_row[k];
      }
    }
  }
  return results;
}

std::string range_table_markdown(const std::vector<RangeResult>& results) {
  // Rows keyed by sensor and size, in the order first seen.
  std::vector<std::pair<std::string, double>> order;
  std::map<std::pair<std::string, double>, std::map<RangeSettings, const RangeResult*>> rows;
  for (const RangeResult& r : results) {
    const auto key = std::make_pair(r.query.sensor, r.query.marker_size_m);
    if (!rows.count(key)) order.push_back(key);
    rows[key][r.settings] = &r;
  }
  auto metres = [](const RangeResult& r) {
    char text[48] = "-";
    if (r.max_distance_m > 0)
      std::snprintf(text, sizeof text, "%.1f-%.1f m", r.min_distance_m, r.max_distance_m);
    return std::string(text);
  };
  std::string out =
      "| sensor | marker | paper settings | iilfm defaults | gain (farthest) | false positives |\n"
      "|---|---|---|---|---|---|\n";
  for (const auto& key : order) {
    const auto& by = rows[key];
    const RangeResult* paper =
        by.count(RangeSettings::kPaper) ? by.at(RangeSettings::kPaper) : nullptr;
    const RangeResult* ours =
        by.count(RangeSettings::kIilfm) ? by.at(RangeSettings::kIilfm) : nullptr;
    char size[32], gain[32] = "-";
    std::snprintf(size, sizeof size, "%.3g m", key.second);
    if (paper && ours && paper->max_distance_m > 0)
      std::snprintf(gain, sizeof gain, "%.2fx", ours->max_distance_m / paper->max_distance_m);
    else if (paper && ours && ours->max_distance_m > 0)
      std::snprintf(gain, sizeof gain, "new");
    const int fp = (paper ? paper->false_positives : 0) + (ours ? ours->false_positives : 0);
    out += "| " + key.first + " | " + size + " | " + (paper ? metres(*paper) : "") + " | " +
           (ours ? metres(*ours) : "") + " | " + gain + " | " + std::to_string(fp) + " |\n";
  }
  return out;
}

}  // namespace iilfm::eval
