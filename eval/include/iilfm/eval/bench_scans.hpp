// The simulated scans every speed measurement uses (Google Benchmark in bench/, `iilfm bench`),
// so figures from the two agree and name the same set-ups.
#pragma once

#include <string>
#include <vector>

#include "iilfm/eval/case.hpp"

namespace iilfm::eval {

struct BenchScan {
  std::string name;
  std::string description;
  SimulatedCase scan;
  PipelineOptions options;  // the sensor preset's defaults, the scene's families and map
};

// "mid40-1", "mid40-10", "mid40-60": the paper's tag wall with 1, 10, 60 integrated Mid-40 frames;
// "vlp16": a VLP-16 sweep of a 0.6 m tag wall at 2 m; "ultrapuck": LiDARTag's ccw_10m (32 rings);
// "os1-128": an OS1-128 sweep (2048 columns) of the tag wall; "grid-60": the paper's 35 + 4 marker
// grid with 60 Mid-40 frames.
std::vector<std::string> bench_scan_names();

// InputError naming the known scans when `name` is not one of them.
void require_bench_scan(const std::string& name);

BenchScan make_bench_scan(const std::string& name, std::uint64_t seed = 1);

}  // namespace iilfm::eval
