// Test helper: simulate a named scene and run the pipeline on it, measuring errors against the
// simulator's ground truth.
#pragma once

#include <string>

#include "iilfm/pipeline.hpp"
#include "iilfm/sim/sim.hpp"

namespace iilfm::testing {

struct CaseErrors {
  bool found = false;            // the scene's first marker was detected with the right id
  int detections = 0;            // all detections in the frame
  int wrong = 0;                 // detections whose family/id is not in the scene
  double mean_corner_error = 0;  // metres, over the lifted corners of the first marker
  double max_corner_error = 0;
  bool pose = false;
  double position_error = 0;      // metres
  double rotation_error_deg = 0;  // angle of R_est^T R_true
  double total_ms = 0;
};

struct CaseSetup {
  std::string scene;   // sim::named_scene name
  std::string sensor;  // sim sensor model and pipeline preset (same names)
  int frames = 1;
  std::uint64_t seed = 1;
  LiftMethod lift = LiftMethod::kPlane;
};

CaseErrors run_sim_case(const CaseSetup& setup);

// The marker map a user would write for `scene`.
MarkerMap map_of(const sim::Scene& scene);

}  // namespace iilfm::testing
