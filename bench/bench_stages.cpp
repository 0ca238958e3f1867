// Per-stage timings on simulated scans (Google Benchmark). Run: build/bin/iilfm_bench_stages
#include <benchmark/benchmark.h>

#include <map>

#include "iilfm/pipeline.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/sim/sim.hpp"

namespace iilfm {
namespace {

struct Scan {
  PointCloud cloud;
  PipelineOptions options;
};

// The paper's set-ups: Mid-40 with `frames` integrated frames of the tag wall, and the ULTRA Puck
// ccw_10m scene.
Scan make_scan(const std::string& scene_name, const std::string& sensor, int frames) {
  const sim::SceneSetup scene = sim::named_scene(scene_name);
  sim::SimOptions sim_options;
  sim_options.T_world_lidar = scene.T_world_lidar;
  sim_options.frames = frames;
  Scan scan;
  scan.cloud = sim::simulate(scene.scene, sim::sensor_model(sensor), sim_options).cloud;
  apply_sensor_preset(find_sensor_preset(sensor), scan.options);
  scan.options.families = {scene.scene.markers.front().family};
  return scan;
}

const Scan& mid40_scan(int frames) {
  static std::map<int, Scan> scans;
  auto it = scans.find(frames);
  if (it == scans.end()) it = scans.emplace(frames, make_scan("tag-wall", "mid40", frames)).first;
  return it->second;
}

const Scan& ultrapuck_scan() {
  static const Scan scan = make_scan("ccw10m", "ultrapuck", 1);
  return scan;
}

void report_points(benchmark::State& state, std::size_t points) {
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(points) * state.iterations(),
                                                  benchmark::Counter::kIsRate);
}

void BM_Project_Mid40(benchmark::State& state) {
  const Scan& scan = mid40_scan(static_cast<int>(state.range(0)));
  SphericalProjector projector(scan.options.projection);
  ProjectedImage image;
  for (auto _ : state) projector.project(scan.cloud, image);
  report_points(state, scan.cloud.size());
}
BENCHMARK(BM_Project_Mid40)->Arg(1)->Arg(10)->Arg(60)->Unit(benchmark::kMillisecond);

void BM_Preprocess_Mid40(benchmark::State& state) {
  const Scan& scan = mid40_scan(60);
  ProjectedImage image;
  SphericalProjector(scan.options.projection).project(scan.cloud, image);
  PreprocessedImage out;
  for (auto _ : state) preprocess(image, scan.options.preprocess, out);
}
BENCHMARK(BM_Preprocess_Mid40)->Unit(benchmark::kMillisecond);

void BM_Detect_Mid40(benchmark::State& state) {
  const Scan& scan = mid40_scan(60);
  ProjectedImage image;
  SphericalProjector(scan.options.projection).project(scan.cloud, image);
  PreprocessedImage pre;
  preprocess(image, scan.options.preprocess, pre);
  auto detector = make_detector(scan.options.families.front(), scan.options.detector);
  std::vector<Detection> found;
  for (auto _ : state) {
    found.clear();
    detector->detect(pre.detect, found);
  }
}
BENCHMARK(BM_Detect_Mid40)->Unit(benchmark::kMillisecond);

void BM_Pipeline(benchmark::State& state, const Scan& (*scan_of)()) {
  const Scan& scan = scan_of();
  Pipeline pipeline(scan.options);
  for (auto _ : state) benchmark::DoNotOptimize(pipeline.process(scan.cloud).markers.size());
  report_points(state, scan.cloud.size());
}
BENCHMARK_CAPTURE(BM_Pipeline, Mid40_60frames, []() -> const Scan& {
  return mid40_scan(60);
})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Pipeline, UltraPuck_ccw10m, ultrapuck_scan)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace iilfm

BENCHMARK_MAIN();
