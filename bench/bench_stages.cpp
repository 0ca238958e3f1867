// Per-stage timings on the shared simulated scans (Google Benchmark).
// Run: build/bin/iilfm_bench_stages [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <map>
#include <string>

#include "bench_support.hpp"
#include "iilfm/frame_window.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/sim/sim.hpp"
#include "iilfm/window_projection.hpp"

namespace iilfm {
namespace {

using bench::scan;

void BM_Read(benchmark::State& state, const std::string& name) {
  const std::string path = "/tmp/iilfm-bench-read-" + name + ".pcd";
  io::write_pcd(path, scan(name).scan.scan.cloud);
  for (auto _ : state) benchmark::DoNotOptimize(io::read_cloud(path).cloud.size());
  bench::report_points(state, scan(name).scan.scan.cloud.size());
  std::remove(path.c_str());
}

// The floor: one streaming read of the points' bytes and one float written per pixel.
void BM_Floor(benchmark::State& state, const std::string& name) {
  const PointCloud& cloud = scan(name).scan.scan.cloud;
  const ProjectedImage& image = bench::projected(name);
  std::vector<float> out(image.intensity.total());
  for (auto _ : state) {
    float sum = 0;
    for (std::size_t i = 0; i < cloud.size(); ++i)
      sum += cloud.x[i] + cloud.y[i] + cloud.z[i] + cloud.intensity[i];
    std::fill(out.begin(), out.end(), sum);
    benchmark::DoNotOptimize(out.data());
  }
  bench::report_points(state, cloud.size());
}

void BM_Project(benchmark::State& state, const std::string& name) {
  const bench::Scan& s = scan(name);
  SphericalProjector projector(s.options.projection);
  ProjectedImage image;
  for (auto _ : state) projector.project(s.scan.scan.cloud, image);
  bench::report_points(state, s.scan.scan.cloud.size());
}

void BM_Preprocess(benchmark::State& state, const std::string& name) {
  const ProjectedImage& image = bench::projected(name);
  PreprocessedImage out;
  for (auto _ : state) preprocess(image, scan(name).options.preprocess, out);
}

void BM_Detect(benchmark::State& state, const std::string& name) {
  const ProjectedImage& image = bench::projected(name);
  PreprocessedImage pre;
  preprocess(image, scan(name).options.preprocess, pre);
  const DetectorOptions& options = scan(name).options.detector;
  std::vector<std::unique_ptr<MarkerDetector>> detectors;
  for (const std::string& family : scan(name).options.families)
    detectors.push_back(make_detector(family, options));
  std::vector<Detection> found;
  const DetectorImages images = detector_images(pre, scan(name).options.preprocess);
  for (auto _ : state) {
    found.clear();
    for (auto& d : detectors) d->detect_images(images, found);
  }
  state.counters["markers"] = static_cast<double>(found.size());
}

void BM_Pipeline(benchmark::State& state, const std::string& name) {
  const bench::Scan& s = scan(name);
  PipelineOptions options = s.options;
  set_threads(options, static_cast<int>(state.range(0)));
  const bench::OpenCvThreads opencv(static_cast<int>(state.range(0)));
  Pipeline pipeline(options);
  for (auto _ : state) benchmark::DoNotOptimize(pipeline.process(s.scan.scan.cloud).markers.size());
  bench::report_points(state, s.scan.scan.cloud.size());
}

// The plane fit alone (the lift's main cost), for every marker the pipeline found, on the
// pipeline's own projected image: CPU time per scan, unlike LiftAndPose's wall time.
void BM_PlaneFit(benchmark::State& state, const std::string& name) {
  const bench::Scan& s = scan(name);
  Pipeline pipeline(s.options);
  const FrameResult& r = pipeline.process(s.scan.scan.cloud);
  std::vector<std::vector<Vec2>> outlines;
  for (const MarkerResult& m : r.markers) outlines.push_back(keypoint_outline(m.detection));
  for (auto _ : state)
    for (const std::vector<Vec2>& outline : outlines)
      benchmark::DoNotOptimize(
          fit_marker_plane(outline, r.image, s.scan.scan.cloud, s.options.plane_fit).inliers);
  state.counters["markers"] = static_cast<double>(outlines.size());
}

// Lift and pose: the pipeline minus its first three stages, timed by the pipeline itself.
void BM_LiftAndPose(benchmark::State& state, const std::string& name) {
  const bench::Scan& s = scan(name);
  Pipeline pipeline(s.options);
  for (auto _ : state) {
    const FrameResult& r = pipeline.process(s.scan.scan.cloud);
    state.SetIterationTime((r.times_ms.lift + r.times_ms.pose) / 1e3);
  }
}

// A sliding 60-frame Mid-40 window, one push per iteration: the window's projection updated
// incrementally (WindowProjector), re-projected whole (SphericalProjector), and the whole
// pipeline on the window. The scan's 60 frames are cut into frames of equal size and cycled.
std::vector<PointCloud> mid40_frames() {
  const PointCloud& all = scan("mid40-60").scan.scan.cloud;
  const std::size_t frames = 60, per = all.size() / frames;
  std::vector<PointCloud> out(frames);
  for (std::size_t f = 0; f < frames; ++f)
    for (std::size_t i = f * per; i < (f + 1) * per; ++i)
      out[f].push_back(all.x[i], all.y[i], all.z[i], all.intensity[i]);
  return out;
}

void BM_WindowPush(benchmark::State& state) {
  static const std::vector<PointCloud> frames = mid40_frames();
  // 0 incremental projection, 1 whole projection, 2 pipeline, 3 pipeline on two threads
  const int mode = static_cast<int>(state.range(0));
  PipelineOptions options = scan("mid40-60").options;
  if (mode == 3) set_threads(options, 2);
  const bench::OpenCvThreads opencv(mode == 3 ? 2 : 1);
  FrameWindow window(frames.size());
  for (const PointCloud& f : frames) window.push(f, {});
  WindowProjector incremental(options.projection);
  SphericalProjector whole(options.projection);
  Pipeline pipeline(options);
  ProjectedImage image;
  std::size_t next = 0;
  for (auto _ : state) {
    window.push(frames[next++ % frames.size()], {});
    if (mode == 0) incremental.project(window, image);
    if (mode == 1) whole.project(window.view(), image);
    if (mode >= 2) benchmark::DoNotOptimize(pipeline.process(window).markers.size());
  }
  state.SetLabel(mode == 0   ? "incremental projection"
                 : mode == 1 ? "whole projection"
                 : mode == 2 ? "pipeline"
                             : "pipeline, 2 threads");
}

// The simulator: 40 Mid-40 frames of the 35-marker grid (400k rays against two walls).
void BM_Simulate(benchmark::State& state) {
  const sim::SceneSetup setup = sim::named_scene("grid");
  sim::SimOptions o;
  o.T_world_lidar = setup.T_world_lidar;
  o.frames = 40;
  const sim::SensorModel sensor = sim::sensor_model("mid40");
  for (auto _ : state) benchmark::DoNotOptimize(sim::simulate(setup.scene, sensor, o).cloud.size());
}

void register_all() {
  benchmark::RegisterBenchmark("Simulate/grid-40", BM_Simulate)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("WindowPush/mid40-60", BM_WindowPush)
      ->ArgName("mode")
      ->Arg(0)
      ->Arg(1)
      ->Arg(2)
      ->Arg(3)
      ->Unit(benchmark::kMillisecond);
  for (const std::string& name : bench::scan_names()) {
    benchmark::RegisterBenchmark(("Read/" + name).c_str(), BM_Read, name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Floor/" + name).c_str(), BM_Floor, name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Project/" + name).c_str(), BM_Project, name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Preprocess/" + name).c_str(), BM_Preprocess, name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Detect/" + name).c_str(), BM_Detect, name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("PlaneFit/" + name).c_str(), BM_PlaneFit, name)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("LiftAndPose/" + name).c_str(), BM_LiftAndPose, name)
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Pipeline/" + name).c_str(), BM_Pipeline, name)
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace
}  // namespace iilfm

int main(int argc, char** argv) { return iilfm::bench::run(argc, argv, iilfm::register_all); }
