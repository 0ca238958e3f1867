// The simulated scans shared by the benchmark programs, simulated once per process on first use.
#pragma once

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "iilfm/eval/bench_scans.hpp"
#include "iilfm/pipeline.hpp"

namespace iilfm::bench {

using Scan = eval::BenchScan;

std::vector<std::string> scan_names();
const Scan& scan(const std::string& name);
const ProjectedImage& projected(const std::string& name);  // the scan projected once

void report_points(benchmark::State& state, std::size_t points);

// A benchmark program's main: registers its benchmarks at run time (they are made per scan).
// OpenCV's parallel loops run on one thread, as in `iilfm` without --threads.
int run(int argc, char** argv, void (*register_benchmarks)());

// OpenCV's parallel loops on `threads` threads while it lives (`iilfm --threads N` sets both).
class OpenCvThreads {
 public:
  explicit OpenCvThreads(int threads);
  ~OpenCvThreads();
  OpenCvThreads(const OpenCvThreads&) = delete;
  OpenCvThreads& operator=(const OpenCvThreads&) = delete;
};

}  // namespace iilfm::bench
