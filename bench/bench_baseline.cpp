// iilfm side by side with the paper's implementation approach (bench/paper_baseline.hpp) on the
// same simulated scans in one run. Built only when PCL is installed.
// Run: build/bin/iilfm_bench_baseline
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include "bench_support.hpp"
#include "paper_baseline.hpp"

namespace iilfm {
namespace {

using bench::scan;

void BM_PaperBaseline(benchmark::State& state, const std::string& name) {
  const bench::Scan& s = scan(name);
  bench::BaselineOptions options;
  options.res_h_deg = static_cast<float>(s.options.projection.res_h_deg);
  options.res_v_deg = static_cast<float>(s.options.projection.res_v_deg);
  if (const auto& fov = s.options.projection.field_of_view) {
    constexpr double kDeg = 180.0 / M_PI;
    const double half_w = std::max(std::abs(fov->azimuth_min), std::abs(fov->azimuth_max)) * kDeg;
    const double half_h =
        std::max(std::abs(fov->elevation_min), std::abs(fov->elevation_max)) * kDeg;
    options.max_angle_width_deg = static_cast<float>(std::min(360.0, 2 * half_w + 1));
    options.max_angle_height_deg = static_cast<float>(std::min(180.0, 2 * half_h + 1));
  }
  if (s.options.preprocess.threshold)
    options.threshold = static_cast<float>(*s.options.preprocess.threshold);
  const std::string& family = s.options.families.front();
  options.family = family.substr(family.find(':') + 1);
  bench::PaperBaseline baseline(options);
  int found = 0;
  for (auto _ : state) found = baseline.detect(s.scan.scan.cloud);
  state.counters["markers"] = found;
  bench::report_points(state, s.scan.scan.cloud.size());
}

void BM_Iilfm(benchmark::State& state, const std::string& name) {
  const bench::Scan& s = scan(name);
  Pipeline pipeline(s.options);
  std::size_t found = 0;
  for (auto _ : state) found = pipeline.process(s.scan.scan.cloud).markers.size();
  state.counters["markers"] = static_cast<double>(found);
  bench::report_points(state, s.scan.scan.cloud.size());
}

void register_all() {
  for (const std::string& name : bench::scan_names()) {
    benchmark::RegisterBenchmark(("PaperBaseline/" + name).c_str(), BM_PaperBaseline, name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Iilfm/" + name).c_str(), BM_Iilfm, name)
        ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace
}  // namespace iilfm

int main(int argc, char** argv) { return iilfm::bench::run(argc, argv, iilfm::register_all); }
