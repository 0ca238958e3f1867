// The detection-range study run by `iilfm eval --suite range`.
#pragma once

#include <string>
#include <vector>

namespace iilfm::cli {

struct RangeStudyArgs {
  std::vector<std::string> sensors = {"mid40",   "avia",    "vlp16",    "vlp16-hires", "ultrapuck",
                                      "os1-64",  "os1-128", "hdl32e",   "hdl64e",      "os0-128",
                                      "os2-128", "xt32",    "pandar40p"};
  std::vector<double> sizes = {0.172, 0.4, 1.0};
  int seeds = 10, required = 9;
  bool footprint = true;
  bool ring_decode = true;
  bool ring_candidates = true;
  bool search_regions = true;
  bool gray_decode = true;
  bool map = true;
};

// Prints the Markdown table on stdout and per-distance counts on stderr.
int run_range_study(const RangeStudyArgs& args);

}  // namespace iilfm::cli
