// `iilfm eval`: runs the pipeline on simulated scans of the paper's experiments and scores it
// against the simulator's ground truth.
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "eval_range.hpp"
#include "iilfm/error.hpp"
#include "iilfm/eval/intensity_study.hpp"
#include "iilfm/eval/report.hpp"
#include "iilfm/eval/suite.hpp"
#include "iilfm/option_names.hpp"

namespace iilfm::cli {
namespace {

struct EvalArgs {
  std::string suite = "quick", lift = "both", json;
  std::string pose_refine = to_string(LidarPoseOptions{}.refine);
  int seeds = 5;
  std::uint64_t first_seed = 1;
  bool markdown = false, footprint = false, quiet = false;
  bool no_edge_refine = false, weight_corners = false, no_ring_decode = false;
  bool no_search_regions = false;
  bool no_gray_decode = false;
  bool ring_candidates = PipelineOptions{}.ring_candidates;
  bool no_map = false;
  double dark_dropout = 0, invalid_fraction = 0;
  bool no_jitter = false;
  std::vector<std::string> range_sensors;
  std::vector<double> range_sizes;
  std::vector<double> distances;        // intensity suite
  std::string intensity_model = "raw";  // intensity suite
  double near = 0;                      // intensity suite
  bool seeds_given = false;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw InputError(message);
}

std::vector<LiftMethod> lifts_of(const std::string& name) {
  if (name == "plane") return {LiftMethod::kPlane};
  if (name == "paper") return {LiftMethod::kPaper};
  if (name == "both") return {LiftMethod::kPlane, LiftMethod::kPaper};
  throw InputError("--lift must be plane, paper or both, got '" + name + "'");
}

// Thresholds and normalisation per sensor and size on simulated scans (docs/sensors.md).
int run_intensity_study(const EvalArgs& a) {
  eval::IntensityQuery query;
  query.seeds = a.seeds_given ? a.seeds : 10;
  require(query.seeds >= 1 && query.seeds <= 1000, "--seeds must be 1..1000");
  query.intensity_model = a.intensity_model;
  if (!a.distances.empty()) query.distances = a.distances;
  query.near_m = a.near;
  const std::vector<std::string> sensors =
      a.range_sensors.empty() ? std::vector<std::string>{query.sensor} : a.range_sensors;
  const std::vector<double> sizes =
      a.range_sizes.empty() ? std::vector<double>{query.marker_size_m} : a.range_sizes;
  for (const std::string& sensor : sensors) {
    for (double size : sizes) {
      query.sensor = sensor;
      query.marker_size_m = size;
      std::cout << eval::intensity_table_markdown(query, eval::intensity_study(query)) << "\n"
                << std::flush;
    }
  }
  return 0;
}

int run_eval(const EvalArgs& a) {
  if (a.suite == "range") {
    RangeStudyArgs range;
    if (!a.range_sensors.empty()) range.sensors = a.range_sensors;
    if (!a.range_sizes.empty()) range.sizes = a.range_sizes;
    range.seeds = a.seeds_given ? a.seeds : 10;
    range.ring_decode = !a.no_ring_decode;
    range.ring_candidates = a.ring_candidates;
    range.search_regions = !a.no_search_regions;
    range.gray_decode = !a.no_gray_decode;
    range.map = !a.no_map;
    range.required = (range.seeds * 9 + 9) / 10;  // 9 of 10
    return run_range_study(range);
  }
  if (a.suite == "intensity") return run_intensity_study(a);
  const std::vector<eval::SuiteSetup> setups = eval::named_suite(a.suite);
  eval::SuiteOptions options;
  options.lifts = lifts_of(a.lift);
  require(a.seeds >= 1 && a.seeds <= 1000, "--seeds must be 1..1000");
  options.seeds.clear();
  for (int i = 0; i < a.seeds; ++i) options.seeds.push_back(a.first_seed + i);
  auto probability = [](double p) { return std::isfinite(p) && p >= 0 && p <= 1; };
  require(probability(a.dark_dropout), "--dark-dropout must be a probability in [0, 1]");
  require(probability(a.invalid_fraction), "--invalid-fraction must be a fraction in [0, 1]");
  options.footprint = a.footprint;
  options.tweaks.edge_refine = !a.no_edge_refine;
  options.tweaks.ring_decode = !a.no_ring_decode;
  options.tweaks.ring_candidates = a.ring_candidates;
  options.tweaks.search_regions = !a.no_search_regions;
  options.tweaks.gray_decode = !a.no_gray_decode;
  options.tweaks.weight_corners = a.weight_corners;
  options.tweaks.pose_refine = pose_refine_named(a.pose_refine);
  options.dark_dropout = a.dark_dropout;
  options.invalid_fraction = a.invalid_fraction;
  if (a.no_jitter) options.jitter_px = 0;
  std::ofstream json_out;
  if (!a.json.empty()) {
    json_out.open(a.json);  // opened first so a bad path fails before minutes of work
    require(json_out.good(), a.json + ": cannot write");
  }

  // Progress goes to stderr when stdout carries the Markdown tables.
  std::ostream& progress_out = a.markdown ? std::cerr : std::cout;
  const eval::SuiteResult result =
      eval::run_suite(a.suite, setups, options, [&](const eval::SetupResult& r) {
        if (!a.quiet || !a.markdown) progress_out << eval::summary_line(r) << std::endl;
      });
  if (a.markdown) std::cout << eval::to_markdown(result);
  if (!a.json.empty()) {
    json_out << eval::to_json(result) << "\n";
    require(json_out.good(), a.json + ": write failed");
  }
  if (!a.quiet) {
    std::cerr << "iilfm eval: " << result.results.size() << " set-up x lift rows, "
              << options.seeds.size() << " seeds, " << result.seconds << " s\n";
  }
  return 0;
}

}  // namespace

Runner register_eval_command(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  EvalArgs& a = *args;
  CLI::App* sub = app.add_subcommand(
      "eval", "Score detection and pose on simulated scans of the paper's experiments");
  sub->add_option("--suite", a.suite,
                  "paper (Tables 1-3 of the paper), quick (one set-up of each table), multi "
                  "(multi-marker maps), range (detection range per sensor and marker size, "
                  "docs/sensors.md) or intensity (thresholds and intensity normalisation per "
                  "sensor, docs/sensors.md)")
      ->capture_default_str();
  sub->add_option("--seeds", a.seeds, "Seeds per set-up (range: 10)")
      ->capture_default_str()
      ->each([&a](const std::string&) { a.seeds_given = true; });
  sub->add_option("--sensors", a.range_sensors, "range: simulated sensors (default: all)");
  sub->add_option("--sizes", a.range_sizes, "range: marker sizes in metres (0.172 0.4 1)");
  sub->add_option("--distances", a.distances, "intensity: distances in metres (2 4 8 12)");
  sub->add_option("--near", a.near,
                  "intensity: also a marker this many metres away in every scan (0: none)");
  sub->add_option(
         "--intensity-model", a.intensity_model,
         "intensity: the simulator's intensity, raw, reflectivity or sensor (the model's own)")
      ->capture_default_str();
  sub->add_option("--first-seed", a.first_seed, "First seed (seeds run consecutively)")
      ->capture_default_str();
  sub->add_option("--lift", a.lift, "Corner lifting: plane, paper or both (same scans)")
      ->capture_default_str();
  sub->add_flag("--markdown", a.markdown, "Print Markdown tables (for docs/accuracy.md)");
  sub->add_option("--json", a.json, "Write every case and summary as JSON here");
  sub->add_flag("--footprint", a.footprint,
                "Simulate beam divergence: intensity averaged over the beam's footprint");
  sub->add_option("--dark-dropout", a.dark_dropout,
                  "Probability that a return from black print is lost")
      ->capture_default_str();
  sub->add_option("--invalid-fraction", a.invalid_fraction,
                  "Fraction of beams emitted as NaN points (dropped before detection)")
      ->capture_default_str();
  sub->add_flag("--no-jitter", a.no_jitter,
                "Same LiDAR placement for every seed (default: a random sub-pixel yaw and pitch "
                "per seed, so the pixel grid falls differently on the markers)");
  sub->add_flag("--no-edge-refine", a.no_edge_refine,
                "Lift the detector's corners as found (no move of the sides to the mid level)");
  sub->add_flag("--no-ring-decode", a.no_ring_decode,
                "Turn off the ring-sample decoding stage (PipelineOptions::ring_decode)");
  sub->add_flag("--ring-candidates,!--no-ring-candidates", a.ring_candidates,
                "Also decode dark squares no detector decoded from the rings (default; "
                "PipelineOptions::ring_candidates)");
  sub->add_flag("--no-map", a.no_map,
                "range: detect without the scene's marker map (iilfm then knows no id)");
  sub->add_flag("--no-search-regions", a.no_search_regions,
                "AprilTag and ArUco search every pixel, not only around quad-shaped boundaries");
  sub->add_flag("--no-gray-decode", a.no_gray_decode,
                "AprilTag decodes the binary image, not the gray one (iilfm settings)");
  sub->add_flag("--weight-corners", a.weight_corners,
                "Weigh corners by their variance in the LiDAR pose fit");
  sub->add_option("--pose-refine", a.pose_refine,
                  "LiDAR pose after Kabsch: none, or points (refined with the marker-plane "
                  "points)")
      ->capture_default_str();
  sub->add_flag("-q,--quiet", a.quiet, "No progress lines");
  return [args]() { return run_eval(*args); };
}

}  // namespace iilfm::cli
