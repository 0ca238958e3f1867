// `iilfm detect IMAGE.png`: an 8-bit intensity image that a driver already projected (Ouster
// publishes one per scan) through the 2-D stages only: preprocessing and detection.
#pragma once

#include <string>

#include "iilfm/pipeline.hpp"

namespace iilfm::cli {

// True for .png / .pgm / .tif(f) inputs.
bool is_image_input(const std::string& path);

struct ImageRunArgs {
  std::string path;
  std::string json_path, image_path;
  bool quiet = false;
};

// Runs preprocessing and detection with `options` (their resolution, if set by a preset or
// --res-h/--res-v, says how coarse the rows are, for square pixels). Markers have pixel corners
// only; every 3-D field is null with the reason.
int run_detect_image(const ImageRunArgs& args, const PipelineOptions& options);

}  // namespace iilfm::cli
