// Suites of evaluation set-ups (the paper's experiments re-created in the simulator), run over
// several seeds and both lifting methods, and summarised as mean and worst.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "iilfm/eval/case.hpp"

namespace iilfm::eval {

struct SuiteSetup {
  std::string group;      // the table it belongs to, e.g. "Table 1: Mid-40, ..."
  std::string name;       // e.g. "Mid-40, 2 m, 40 frames"
  std::string published;  // what the paper published for this group, printed under its table
  CaseSpec spec;
};

// "paper": Table 1 (Mid-40, 17.2 cm tag36h11 at 2, 3, 4 m; 40 and 100 frames), Table 2 (2 m, 40
// frames, LiDAR pitched and yawed by +-15 deg), Table 3 (ULTRA Puck, ccw10m).
// Then the ArUco cases: the paper's VLP-16 with a 40 cm DICT_ARUCO_ORIGINAL marker (one sweep at
// 1, 1.5 and 2 m, and a VLP-16 Hi-Res at 2 and 3 m), and a Mid-40 with the 16 cm DICT_4X4_50
// marker of the paper's grid at 2 m.
// "quick": one set-up of each table (2 m / 40 frames, yaw +15 deg, ccw10m) and the Mid-40 ArUco
// case, for CI.
// "multi": multi-marker maps: the 35-tag grid (Mid-40, 3.5 m), the room scene (Avia, four
// markers near and far) and the around scene (OS1-64, five markers on four walls).
// InputError for other names.
std::vector<SuiteSetup> named_suite(const std::string& name);
std::vector<std::string> suite_names();

// Mean and worst of one figure over the cases that have it.
struct Stat {
  int count = 0;
  double sum = 0, worst = 0;
  void add(double value, double worst_value);
  void add(double value) { add(value, value); }
  double mean() const { return count > 0 ? sum / count : 0; }
};

// Claimed uncertainty against the observed error over cases: the ratio of the RMS error to the
// RMS claimed sigma should be near 1 (0.5-2 over a handful of seeds), and the mean NEES near 6.
struct Consistency {
  int count = 0;
  double error_sq = 0, sigma_sq = 0, nees = 0;
  void add(double error, double sigma, double nees_value);
  double rms_error() const { return count > 0 ? std::sqrt(error_sq / count) : 0; }
  double rms_sigma() const { return count > 0 ? std::sqrt(sigma_sq / count) : 0; }
  double ratio() const { return sigma_sq > 0 ? std::sqrt(error_sq / sigma_sq) : 0; }
  double mean_nees() const { return count > 0 ? nees / count : 0; }
};

struct Summary {
  int cases = 0, visible = 0, detected = 0, false_positives = 0, wrong_ids = 0, poses = 0;
  Stat corner_error;     // per case mean; worst = the worst single corner
  Stat size_error;       // signed: per case mean side length minus true size, metres
  Stat marker_position;  // metres, of T_lidar_marker
  Stat marker_rotation_deg;
  Stat position;  // metres, of T_world_lidar
  Stat rotation_deg;
  Stat time_ms;
  Consistency marker_position_claim, marker_rotation_claim;  // metres, degrees
  Consistency position_claim, rotation_claim;                // of T_world_lidar
};

Summary summarize(const std::vector<CaseScore>& cases);

struct SetupResult {
  SuiteSetup setup;
  LiftMethod lift = LiftMethod::kPlane;
  std::vector<std::uint64_t> seeds;
  std::vector<CaseScore> cases;  // one per seed
  Summary summary;
};

struct SuiteOptions {
  std::vector<std::uint64_t> seeds = {1, 2, 3, 4, 5};
  std::vector<LiftMethod> lifts = {LiftMethod::kPlane, LiftMethod::kPaper};
  // Physics switched on for every set-up on top of its own options.
  bool footprint = false;
  PipelineTweaks tweaks;  // pipeline options changed from the defaults, for before/after
  double dark_dropout = 0;
  double invalid_fraction = 0;
  // CaseSpec::jitter_px for every set-up: on by default, so that errors and claimed sigmas are
  // compared over sub-pixel placements rather than one.
  double jitter_px = 1;
};

struct SuiteResult {
  std::string suite;
  SuiteOptions options;
  std::vector<SetupResult> results;  // set-up major, then lift, in suite order
  double seconds = 0;                // wall time of the whole run
};

// Each seed's scan is simulated once and run through every lifting method. `progress` (optional)
// is called after each set-up and lift with the result so far.
SuiteResult run_suite(const std::string& name, const std::vector<SuiteSetup>& setups,
                      const SuiteOptions& options,
                      const std::function<void(const SetupResult&)>& progress = {});

}  // namespace iilfm::eval
