// `iilfm eval --suite range`: the detection-range study of docs/sensors.md.
#include "eval_range.hpp"

#include <chrono>
#include <iostream>

#include "iilfm/eval/detection_range.hpp"

namespace iilfm::cli {

int run_range_study(const RangeStudyArgs& a) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<eval::RangeResult> all;
  for (const std::string& sensor : a.sensors) {
    for (double size : a.sizes) {
      eval::RangeQuery query;
      query.sensor = sensor;
      query.marker_size_m = size;
      query.seeds = a.seeds;
      query.required = a.required;
      query.footprint = a.footprint;
      query.ring_decode = a.ring_decode;
      query.ring_candidates = a.ring_candidates;
      query.search_regions = a.search_regions;
      query.gray_decode = a.gray_decode;
      query.map = a.map;
      const std::vector<eval::RangeResult> results =
          eval::detection_range(query, {eval::RangeSettings::kPaper, eval::RangeSettings::kIilfm});
      for (const eval::RangeResult& r : results) {
        std::cerr << sensor << " " << size << " m " << eval::settings_name(r.settings) << ":";
        for (const auto& [distance, found] : r.found) std::cerr << " " << distance << "m:" << found;
        std::cerr << " -> " << r.max_distance_m << " m\n";
        all.push_back(r);
      }
    }
  }
  std::cout << eval::range_table_markdown(all);
  std::cerr << "iilfm eval --suite range: "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
            << " s\n";
  return 0;
}

}  // namespace iilfm::cli
