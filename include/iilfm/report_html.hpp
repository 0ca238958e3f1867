// The HTML report: one self-contained page (no server, works offline) with an interactive 3-D view
// of the cloud coloured by intensity, each detected marker's outline, id and axes, the LiDAR pose
// in the world, the preprocessed intensity image with the detections, and the marker, pose and
// timing tables. The three.js viewer is bundled into the program at build time (web/).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "iilfm/marker_map.hpp"
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

// The page for `frames`; it shows the last one. InputError when built without the report or when
// `frames` is empty.
std::string html_report(const std::vector<HtmlFrame>& frames,
                        const HtmlReportOptions& options = {});

// Writes html_report() to `path`; InputError("<path>: ...") when it cannot.
void write_html_report(const std::string& path, const std::vector<HtmlFrame>& frames,
                       const HtmlReportOptions& options = {});

// The report of a recording: the LiDAR trajectory in the world with the map's markers, x/y/z
// against time, a table of every frame's detections and pose, and one frame shown in full (cloud,
// image, tables) as in html_report(). Per frame it keeps only a small summary (about 100 bytes
// plus a few per marker), so a long recording gives a page not much larger than one frame's.
struct HtmlFrameData;  // src/report_html.cpp

class HtmlSequenceReport {
 public:
  explicit HtmlSequenceReport(HtmlReportOptions options = {});

  // The mapped markers are drawn in the trajectory view.
  void set_map(const MarkerMap& map);
  // One frame's result as written to --jsonl: result_to_json() plus "frame" and "timestamp".
  void add(const nlohmann::json& line);
  // The frame shown in full, `line_index` the add() call (0-based) it belongs to. Its subsampled
  // points and picture are copied now (the result's buffers are reused by the next frame) and
  // encoded by page(); a later call replaces it.
  void show(const HtmlFrame& frame, std::size_t line_index);
  bool showing() const { return shown_ != nullptr; }
  std::size_t frames() const { return summaries_.size(); }

  // InputError when built without the report or when no frame was added.
  std::string page() const;
  void write(const std::string& path) const;

 private:
  HtmlReportOptions options_;
  nlohmann::json map_markers_ = nlohmann::json::array();
  nlohmann::json keys_ = nlohmann::json::array();  // "family/id" of every marker seen
  std::map<std::string, std::size_t> key_index_;
  nlohmann::json summaries_ = nlohmann::json::array();
  std::shared_ptr<const HtmlFrameData> shown_;  // copied now, encoded by page()
  std::size_t shown_index_ = 0;
};

}  // namespace iilfm
