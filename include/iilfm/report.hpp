// What a frame's result looks like to users: the JSON of the CLI contract (ARCHITECTURE.md) and an
// overlay picture of the intensity image with the detections drawn on it.
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "iilfm/pipeline.hpp"

namespace iilfm {

struct InputInfo {
  std::string path;
  CloudStats stats;
  double read_ms = 0;
  std::string resolution_source;  // e.g. "preset mid40", "given", "estimated (ring field)"
};

nlohmann::json result_to_json(const FrameResult& result, const InputInfo& input);

// BGR picture: the gray intensity image (unobserved pixels dark green), scaled up so pixels are
// square in angle and small images stay readable, each detection's outline, numbered corners
// (1 = top-left ... 4 = bottom-left) and id.
cv::Mat draw_overlay(const FrameResult& result);

// Writes draw_overlay's picture, as PNG or (for a .jpg/.jpeg path) JPEG; InputError naming `path`
// for another extension or when it cannot be written.
void write_overlay(const std::string& path, const FrameResult& result);
// The extension check of write_overlay alone, for callers that refuse bad paths up front.
void check_overlay_path(const std::string& path);

}  // namespace iilfm
