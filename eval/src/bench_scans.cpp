#include "iilfm/eval/bench_scans.hpp"

#include "iilfm/error.hpp"

namespace iilfm::eval {

namespace {

struct Recipe {
  const char* name;
  const char* description;
  const char* scene;
  const char* sensor;
  int frames;
  double marker_size_m;  // 0: the scene's own
  double distance_m;     // 0: the scene's own
};

constexpr Recipe kRecipes[] = {
    {"mid40-1", "Mid-40, 1 frame, tag wall at 2 m", "tag-wall", "mid40", 1, 0, 0},
    {"mid40-10", "Mid-40, 10 frames, tag wall at 2 m", "tag-wall", "mid40", 10, 0, 0},
    {"mid40-60", "Mid-40, 60 frames, tag wall at 2 m", "tag-wall", "mid40", 60, 0, 0},
    {"vlp16", "VLP-16 sweep, 0.6 m tag at 2 m", "tag-wall", "vlp16", 1, 0.6, 2},
    {"ultrapuck", "ULTRA Puck sweep (32 rings), ccw_10m", "ccw10m", "ultrapuck", 1, 0, 0},
    {"os1-128", "OS1-128 sweep (2048 columns), 0.6 m tag at 3 m", "tag-wall", "os1-128", 1, 0.6, 3},
    {"grid-60", "Mid-40, 60 frames, 35 + 4 marker grid at 4 m", "paper-grid", "mid40", 60, 0, 0},
};

}  // namespace

std::vector<std::string> bench_scan_names() {
  std::vector<std::string> names;
  for (const Recipe& r : kRecipes) names.emplace_back(r.name);
  return names;
}

void require_bench_scan(const std::string& name) {
  for (const Recipe& r : kRecipes)
    if (name == r.name) return;
  std::string known;
  for (const std::string& n : bench_scan_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown benchmark scan '" + name + "' (known: " + known + ")");
}

BenchScan make_bench_scan(const std::string& name, std::uint64_t seed) {
  require_bench_scan(name);
  for (const Recipe& r : kRecipes) {
    if (name != r.name) continue;
    CaseSpec spec;
    spec.scene = r.scene;
    spec.sensor = r.sensor;
    spec.frames = r.frames;
    if (r.marker_size_m > 0) spec.scene_params.marker_size_m = r.marker_size_m;
    if (r.distance_m > 0) spec.scene_params.distance_m = r.distance_m;
    BenchScan scan{r.name, r.description, simulate_case(spec, seed), {}};
    scan.options = pipeline_options_for(scan.scan, LiftMethod::kPlane);
    return scan;
  }
  return {};  // not reached: require_bench_scan threw
}

}  // namespace iilfm::eval
