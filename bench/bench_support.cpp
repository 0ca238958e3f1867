#include "bench_support.hpp"

#include <map>
#include <opencv2/core/utility.hpp>

namespace iilfm::bench {

std::vector<std::string> scan_names() { return eval::bench_scan_names(); }

const Scan& scan(const std::string& name) {
  static std::map<std::string, Scan> scans;
  auto it = scans.find(name);
  if (it == scans.end()) it = scans.emplace(name, eval::make_bench_scan(name)).first;
  return it->second;
}

const ProjectedImage& projected(const std::string& name) {
  static std::map<std::string, ProjectedImage> images;
  auto it = images.find(name);
  if (it == images.end()) {
    it = images.emplace(name, ProjectedImage{}).first;
    SphericalProjector(scan(name).options.projection)
        .project(scan(name).scan.scan.cloud, it->second);
  }
  return it->second;
}

void report_points(benchmark::State& state, std::size_t points) {
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(points) * state.iterations(),
                                                  benchmark::Counter::kIsRate);
}

OpenCvThreads::OpenCvThreads(int threads) { cv::setNumThreads(threads); }
OpenCvThreads::~OpenCvThreads() { cv::setNumThreads(1); }

int run(int argc, char** argv, void (*register_benchmarks)()) {
  // As `iilfm` runs them without --threads (apps/opencv_threads.hpp); the benchmarks of two
  // threads raise it (OpenCvThreads).
  cv::setNumThreads(1);
  benchmark::Initialize(&argc, argv);
  register_benchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace iilfm::bench
