// A long recording through the sequence path (FrameSource over a folder of PCDs, a 3-frame
// FrameWindow, the pipeline and the JSON report per frame) keeps its memory constant: after a
// warm-up the resident set size stops growing. IILFM_LONG_FRAMES sets the length (default 300, 100
// under a sanitizer; docs/reliability.md records a 10 000-frame run). Leaks are LeakSanitizer's
// job in the ASan build.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "iilfm/frame_window.hpp"
#include "iilfm/io/frame_source.hpp"
#include "iilfm/pipeline.hpp"
#include "iilfm/report.hpp"
#include "iilfm/sensor.hpp"
#include "iilfm/sim/scenes.hpp"
#include "iilfm/sim/simulate.hpp"
#include "io/io_test_support.hpp"
#include "process_rss.hpp"

namespace iilfm {
namespace {

constexpr int kDistinctSweeps = 6;
constexpr std::size_t kWarmupFrames = 60;

std::size_t frames_to_run() {
  const char* env = std::getenv("IILFM_LONG_FRAMES");
  // Sanitizer builds run 20-40x slower and check leaks, not RSS: a shorter run does.
  return env ? std::strtoul(env, nullptr, 10) : testing::kSanitizedMemory ? 100 : 300;
}

// VLP-16 sweeps of the tag wall at 2 m, each with its own noise and 1% of points invalid (NaN),
// so frames differ in content and in valid point count.
void write_sweeps(const io::testing::TempDir& dir) {
  sim::SceneParams params;
  params.distance_m = 2.0;
  params.marker_size_m = 0.6;
  const sim::SceneSetup setup = sim::named_scene("tag-wall", params);
  for (int k = 0; k < kDistinctSweeps; ++k) {
    sim::SimOptions options;
    options.T_world_lidar = setup.T_world_lidar;
    options.seed = 100 + k;
    options.invalid_fraction = 0.01;
    const sim::SimResult r = sim::simulate(setup.scene, sim::vlp16(), options);
    io::write_pcd(dir.file("sweep_" + std::to_string(k) + ".pcd"), r.cloud);
  }
}

TEST(LongRun, MemoryStaysFlatOverASequence) {
  const std::size_t frames = frames_to_run();
  ASSERT_GT(frames, kWarmupFrames);
  io::testing::TempDir dir;
  write_sweeps(dir);

  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("vlp16"), options);
  options.marker_size = 0.6;
  Pipeline pipeline(options);
  FrameWindow window(3);

  const std::size_t rss_start = testing::resident_bytes();
  std::size_t rss_warm = 0, processed = 0, with_markers = 0;
  while (processed < frames) {
    // The folder is replayed from the start each time it runs out: a fresh source per pass, as
    // a user walking many recordings would open one after another.
    auto source = io::open_frame_source(dir.file("."), "");
    io::Frame frame;
    while (processed < frames && source->next(frame)) {
      window.push(frame.loaded.cloud, frame.loaded.stats);
      const FrameResult& result = pipeline.process(window);
      const std::string json = result_to_json(result, {frame.source, window.stats(), 0, ""}).dump();
      ASSERT_FALSE(json.empty());
      with_markers += result.markers.empty() ? 0 : 1;
      if (++processed == kWarmupFrames) rss_warm = testing::resident_bytes();
    }
  }
  const std::size_t rss_end = testing::resident_bytes();
  std::printf("long run: %zu frames, RSS start %.1f MiB, after %zu frames %.1f MiB, end %.1f MiB\n",
              processed, rss_start / 1048576.0, kWarmupFrames, rss_warm / 1048576.0,
              rss_end / 1048576.0);
  // The marker is found: the run exercised detection and lifting, not only empty images.
  EXPECT_GT(with_markers, processed / 2);
  if (testing::kSanitizedMemory) GTEST_SKIP() << "RSS is not meaningful under a sanitizer";
  ASSERT_GT(rss_warm, 0u) << "/proc/self/statm unreadable";
  // Frame buffers are reused; a few MiB allow for allocator slack, not for a per-frame leak
  // (a 30 000-point frame is 0.5 MiB, so keeping one per frame would exceed this in 10 frames).
  EXPECT_LT(static_cast<double>(rss_end) - static_cast<double>(rss_warm), 4.0 * 1048576)
      << "RSS grew from " << rss_warm << " to " << rss_end << " bytes";
}

}  // namespace
}  // namespace iilfm
