// The HTML report: one self-contained page (no server, works offline) with an interactive 3-D view
// of the cloud coloured by intensity, each detected marker's outline, id and axes, the LiDAR pose
// in the world, the preprocessed intensity image with the detections, and the marker, pose and
// timing tables. The three.js viewer is bundled into the program at build time (web/).
#pragma once

#include <string>
#include <vector>

#include "iilfm/pipeline.hpp"
#include "iilfm/report.hpp"

namespace iilfm {

// One frame of a report: its result, where it came from, and its points (the result's index
// image refers to them).
struct HtmlFrame {
  const FrameResult* result = nullptr;
  InputInfo input;
  PointView points;
};

struct HtmlReportOptions {
  std::string title = "iilfm detection report";
  // The 3-D view shows every k-th point so that at most this many are embedded (16 bytes each
  // in the file, as base64); the page says how many it shows.
  std::size_t max_points = 100'000;
};

// False when the program was built with -DIILFM_HTML_REPORT=OFF (no viewer bundled).
bool html_report_available();

// The page for `frames`. The data layout holds a list of frames so sequences can be shown; this
// version shows the last frame (sequences add the trajectory and per-frame detections later).
// InputError when built without the report or when `frames` is empty.
std::string html_report(const std::vector<HtmlFrame>& frames,
                        const HtmlReportOptions& options = {});

// Writes html_report() to `path`; InputError("<path>: ...") when it cannot.
void write_html_report(const std::string& path, const std::vector<HtmlFrame>& frames,
                       const HtmlReportOptions& options = {});

}  // namespace iilfm
