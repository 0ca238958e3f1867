// `iilfm bench`: end-to-end speed on simulated scans. Every stage's median and spread over
// repeated runs of one warm pipeline, points per second, peak memory, and each stage's ratio to a
// floor (one streaming read of the same point bytes), so "near the hardware limit" is a number.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"
#include "iilfm/error.hpp"
#include "iilfm/eval/bench_scans.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "opencv_threads.hpp"

namespace iilfm::cli {

namespace {

struct BenchArgs {
  std::vector<std::string> scans;
  int repeat = 30;
  int threads = 1;
  bool markdown = false;
};

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Spread {
  double median = 0, p10 = 0, p90 = 0;
};

Spread spread_of(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  auto at = [&](double q) {
    return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1) + 0.5)];
  };
  return values.empty() ? Spread{} : Spread{at(0.5), at(0.1), at(0.9)};
}

// The floor: one pass reading every byte the projection must read (x, y, z, intensity) and
// writing one float per pixel, as fast as memory allows.
double floor_ms(const PointCloud& cloud, std::size_t pixels) {
  static std::vector<float> image;
  image.assign(pixels, 0.0f);
  const auto start = Clock::now();
  float sum = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    sum += cloud.x[i] + cloud.y[i] + cloud.z[i] + cloud.intensity[i];
  std::fill(image.begin(), image.end(), sum);
  const double ms = ms_since(start);
  volatile float sink = image[pixels / 2];
  (void)sink;
  return ms;
}

long peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;  // kB on Linux
}

struct Row {
  std::string name, description;
  std::size_t points = 0;
  int width = 0, height = 0, markers = 0;
  Spread read, project, preprocess, detect, lift, pose, total, floor;
};

Row measure(const std::string& name, const BenchArgs& args) {
  eval::BenchScan scan = eval::make_bench_scan(name);
  set_threads(scan.options, args.threads);
  const PointCloud& cloud = scan.scan.scan.cloud;
  const std::string path = "/tmp/iilfm-bench-" + std::to_string(::getpid()) + "-" + name + ".pcd";
  io::write_pcd(path, cloud);

  Pipeline pipeline(scan.options);
  for (int i = 0; i < 3; ++i) pipeline.process(cloud);  // warm buffers and caches
  std::vector<double> read, project, preprocess, detect, lift, pose, total, floor;
  Row row;
  row.name = name;
  row.description = scan.description;
  row.points = cloud.size();
  for (int i = 0; i < args.repeat; ++i) {
    auto start = Clock::now();
    io::read_cloud(path);
    read.push_back(ms_since(start));
    start = Clock::now();
    const FrameResult& r = pipeline.process(cloud);
    total.push_back(ms_since(start));
    project.push_back(r.times_ms.project);
    preprocess.push_back(r.times_ms.preprocess);
    detect.push_back(r.times_ms.detect);
    lift.push_back(r.times_ms.lift);
    pose.push_back(r.times_ms.pose);
    row.width = r.image.geometry.width;
    row.height = r.image.geometry.height;
    row.markers = static_cast<int>(r.markers.size());
    floor.push_back(floor_ms(
        cloud, static_cast<std::size_t>(row.width) * static_cast<std::size_t>(row.height)));
  }
  std::remove(path.c_str());
  row.read = spread_of(read);
  row.project = spread_of(project);
  row.preprocess = spread_of(preprocess);
  row.detect = spread_of(detect);
  row.lift = spread_of(lift);
  row.pose = spread_of(pose);
  row.total = spread_of(total);
  row.floor = spread_of(floor);
  return row;
}

std::string cell(const Spread& s) {
  char text[64];
  std::snprintf(text, sizeof text, "%.2f (%.2f-%.2f)", s.median, s.p10, s.p90);
  return text;
}

void print(const std::vector<Row>& rows, const BenchArgs& args) {
  std::printf(
      "iilfm bench: %d runs per scan after 3 warm-up runs, threads %d (projection, preprocessing,"
      " lift); times in ms, median (10th-90th percentile)\n\n",
      args.repeat, args.threads);
  const char* sep = args.markdown ? " | " : "  ";
  if (args.markdown) {
    std::printf(
        "| scan | points | image | markers | read | project | preprocess | detect | lift |"
        " pose | total (no read) | Mpoints/s | floor | project / floor | total / floor |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  }
  for (const Row& r : rows) {
    const double mpps =
        r.total.median > 0 ? static_cast<double>(r.points) / r.total.median / 1e3 : 0;
    const double floor = std::max(r.floor.median, 1e-6);
    std::printf("%s%s%s%zu%s%dx%d%s%d%s%s%s%s%s%s%s%s%s%s%s%s%s%s%s%.1f%s%.3f%s%.1f%s%.1f%s\n",
                args.markdown ? "| " : "", r.name.c_str(), sep, r.points, sep, r.width, r.height,
                sep, r.markers, sep, cell(r.read).c_str(), sep, cell(r.project).c_str(), sep,
                cell(r.preprocess).c_str(), sep, cell(r.detect).c_str(), sep, cell(r.lift).c_str(),
                sep, cell(r.pose).c_str(), sep, cell(r.total).c_str(), sep, mpps, sep,
                r.floor.median, sep, r.project.median / floor, sep, r.total.median / floor,
                args.markdown ? " |" : "");
  }
  std::printf("\npeak resident memory: %ld MB\n", peak_rss_mb());
  if (!args.markdown) {
    std::printf("\nscans:\n");
    for (const Row& r : rows) std::printf("  %-10s %s\n", r.name.c_str(), r.description.c_str());
  }
}

}  // namespace

Runner register_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* cmd = app.add_subcommand("bench", "Time every stage on simulated scans");
  std::string known;
  for (const std::string& n : eval::bench_scan_names()) known += (known.empty() ? "" : ", ") + n;
  cmd->add_option("--scan", args->scans, "Scans to time (default: all of " + known + ")");
  cmd->add_option("--repeat", args->repeat, "Timed runs per scan")->check(CLI::Range(1, 100000));
  cmd->add_option(
         "--threads", args->threads,
         "threads for projecting and preprocessing large clouds, for running several families' "
         "detectors at once, for lifting markers and for OpenCV's own parallel loops (default 1)")
      ->check(CLI::Range(1, 64));
  cmd->add_flag("--markdown", args->markdown, "Print a Markdown table");
  return [args] {
    use_opencv_threads(args->threads);
    std::vector<std::string> names = args->scans.empty() ? eval::bench_scan_names() : args->scans;
    for (const std::string& n : names) eval::require_bench_scan(n);
    std::vector<Row> rows;
    for (const std::string& n : names) rows.push_back(measure(n, *args));
    print(rows, *args);
    return 0;
  };
}

}  // namespace iilfm::cli
