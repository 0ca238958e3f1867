// Thresholds and intensity normalisation measured on simulated scans (`iilfm eval --suite
// intensity`, docs/sensors.md): how often a marker is found at each distance with each threshold
// (fixed, Otsu, local) with and without normalisation, for either intensity model of the
// simulator, and how many detections appear on the same scene without a marker.
#pragma once

#include <string>
#include <vector>

#include "iilfm/eval/case.hpp"

namespace iilfm::eval {

struct IntensityVariant {
  std::string name;       // e.g. "fixed 40 + range"
  std::string threshold;  // as --threshold: a number, "otsu", "local"; "" = the preset's
  std::string normalise;  // as --normalise-intensity; "" = the preset's
};

// The variants compared by default: the preset's settings, fixed 40, Otsu and local, each
// without and with range (and range-incidence) normalisation.
std::vector<IntensityVariant> default_intensity_variants();

struct IntensityQuery {
  std::string sensor = "os1-128";
  double marker_size_m = 1.0;
  std::string intensity_model = "raw";  // "raw" or "reflectivity" (sim::PhysicsRequest)
  std::vector<double> distances = {2, 4, 8, 12};
  int seeds = 10;
  bool footprint = true;
  // > 0: a second marker (id 1, same size) on a board this far from the LiDAR, off to the side,
  // in every scan, so one threshold must serve both ranges in one image.
  double near_m = 0;
  std::vector<IntensityVariant> variants = default_intensity_variants();
};

struct IntensityResult {
  IntensityVariant variant;
  std::vector<std::pair<double, int>> found;  // distance -> seeds with the (far) marker found
  std::vector<int> found_near, found_both;    // per distance, with near_m
  int false_positives = 0;                    // wrong or extra detections on the marker scans
  int empty_scene_detections = 0;             // any detection on the same scans without the marker
};

// Each seed pitches and yaws the LiDAR a little, as the range study does. Every variant sees the
// same scans.
std::vector<IntensityResult> intensity_study(const IntensityQuery& query);

// Markdown: one row per variant, found/seeds per distance, false positives.
std::string intensity_table_markdown(const IntensityQuery& query,
                                     const std::vector<IntensityResult>& results);

}  // namespace iilfm::eval
