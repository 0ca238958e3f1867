#include "detect_sequence.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>

#include "iilfm/error.hpp"
#include "iilfm/frame_window.hpp"
#include "iilfm/io/bag.hpp"
#include "iilfm/io/frame_source.hpp"
#include "iilfm/io/read_ahead.hpp"
#include "iilfm/report.hpp"
#include "iilfm/report_html.hpp"
#include "progress_bar.hpp"
#include "text_output.hpp"

namespace iilfm::cli {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// An output written line by line and flushed after each line, so what was written before a
// failure is complete and readable: a file, or stdout for "-".
class LineFile {
 public:
  explicit LineFile(const std::string& path) : path_(path) {
    if (path.empty() || is_stdout(path)) return;
    file_.open(path);
    if (!file_) throw file_error(path, "cannot open for writing");
  }
  bool active() const { return !path_.empty(); }
  void write(const std::string& line) {
    if (!active()) return;
    std::ostream& out = is_stdout(path_) ? std::cout : file_;
    if (!(out << line << '\n') || !out.flush())
      throw file_error(is_stdout(path_) ? "stdout" : path_, "write failed");
  }

 private:
  std::string path_;
  std::ofstream file_;
};

// "1629371234.123456789 tx ty tz qx qy qz qw": the TUM RGB-D trajectory format.
// The pipeline's own refusals (an image over --max-image-pixels) name the frame.
const FrameResult& process_frame(Pipeline& pipeline, const FrameWindow& window,
                                 const std::string& source) {
  try {
    return pipeline.process(window);
  } catch (const InputError& e) {
    throw file_error(source, std::string(e.what()) + " (--max-image-pixels raises the limit)");
  }
}

std::string tum_line(double stamp_s, const Isometry3& T) {
  const Vec3 t = T.translation();
  const Eigen::Quaterniond q(T.linear());
  char line[256];
  std::snprintf(line, sizeof line, "%.9f %.6f %.6f %.6f %.9f %.9f %.9f %.9f", stamp_s, t.x(), t.y(),
                t.z(), q.x(), q.y(), q.z(), q.w());
  return line;
}

// A frame (window) without valid points: no image to make, but the line keeps the sequence whole.
nlohmann::json empty_result(const InputInfo& info) {
  return {{"input",
           {{"path", info.path},
            {"points", info.stats.points_in_file},
            {"valid_points", 0},
            {"skipped_non_finite", info.stats.non_finite},
            {"skipped_zero", info.stats.zero}}},
          {"image", nullptr},
          {"markers", nlohmann::json::array()},
          {"pose", nullptr},
          {"pose_missing_reason", "no valid points"},
          {"timing_ms",
           {{"read", info.read_ms},
            {"project", 0},
            {"preprocess", 0},
            {"detect", 0},
            {"lift", 0},
            {"pose", 0},
            {"total", info.read_ms}}}};
}

struct Counts {
  std::size_t frames = 0, results = 0, with_markers = 0, with_pose = 0;
  // Results whose fixed threshold lay above every intensity: replaced by Otsu's (a preset's), or
  // kept (the user's); the last such threshold.
  std::size_t threshold_replaced = 0, threshold_above_all = 0, no_intensity = 0;
  // Results whose markers were found only at Otsu's threshold (PipelineOptions::retry_with_otsu).
  std::size_t found_at_otsu = 0;
  double threshold = 0;
  // Results with a marker whose measured size disagrees with the one given
  // (MarkerResult::size_disagrees), and the first such marker, as "family/id".
  std::size_t size_disagrees = 0;
  std::string size_disagrees_first;
};

// Whether this result is the one the report shows in full: the selected frame, else the latest
// with markers (the first frame stands in until one has them).
bool shown_in_full(const SequenceArgs& args, const HtmlSequenceReport& html, std::size_t frame,
                   bool has_markers) {
  if (args.html_frame >= 0) return frame == static_cast<std::size_t>(args.html_frame);
  return has_markers || !html.showing();
}

}  // namespace

bool is_sequence_run(const SequenceArgs& args) {
  return !args.jsonl_path.empty() || !args.tum_path.empty() || !args.topic.empty() ||
         io::is_bag_path(args.input);
}

int run_detect_sequence(const SequenceArgs& args, const PipelineFactory& make_options) {
  std::optional<Pipeline> pipeline;  // made from the first window (it may estimate resolution)
  std::string resolution_source;     // where the pipeline's resolution came from
  // Frames are read on a thread of their own while the one before is detected.
  const std::unique_ptr<io::FrameSource> source =
      io::read_ahead(io::open_frame_source(args.input, args.topic));
  LineFile jsonl(args.jsonl_path), tum(args.tum_path);
  std::optional<HtmlSequenceReport> html;
  if (!args.html_path.empty()) {
    HtmlReportOptions options;
    options.title = "iilfm report: " + source->name();
    html.emplace(options);
  }
  FrameWindow window = args.window_seconds > 0 ? FrameWindow::over_seconds(args.window_seconds)
                                               : FrameWindow(static_cast<std::size_t>(args.frames));
  double first_stamp = 0, last_stamp = 0;
  ProgressBar progress(source->total(), !args.quiet);
  Counts counts;
  std::size_t window_first = 0;
  std::vector<std::size_t> window_indices;

  try {
    io::Frame frame;
    while (true) {
      const Clock::time_point start = Clock::now();
      if (!source->next(frame)) break;
      ++counts.frames;
      window.push(frame.loaded.cloud, frame.loaded.stats, frame.stamp_s);
      if (counts.frames == 1) first_stamp = frame.stamp_s;
      last_stamp = frame.stamp_s;
      window_indices.push_back(frame.index);
      while (window_indices.size() > window.size()) window_indices.erase(window_indices.begin());
      window_first = window_indices.front();
      if (!window.full()) continue;

      const PointView cloud = window.view();
      InputInfo info{frame.source, window.stats(), ms_since(start), resolution_source};
      nlohmann::json line;
      if (cloud.empty()) {
        line = empty_result(info);
      } else {
        if (!pipeline) {
          pipeline.emplace(make_options(window.copy(), resolution_source));
          info.resolution_source = resolution_source;
          if (html && pipeline->options().map) html->set_map(*pipeline->options().map);
        }
        const FrameResult& result = process_frame(*pipeline, window, frame.source);
        line = result_to_json(result, info);
        if (html && shown_in_full(args, *html, frame.index, !result.markers.empty()))
          html->show(HtmlFrame{&result, info, cloud}, counts.results);
        if (result.preprocessed.no_intensity) {
          ++counts.no_intensity;
        } else if (result.preprocessed.replaced_threshold) {
          ++counts.threshold_replaced;
          counts.threshold = *result.preprocessed.replaced_threshold;
        } else if (result.preprocessed.threshold_above_all) {
          ++counts.threshold_above_all;
          counts.threshold = result.preprocessed.threshold;
        }
        if (result.threshold_retry && result.threshold_retry->found > 0 &&
            !result.threshold_retry->local) {
          ++counts.found_at_otsu;
          counts.threshold = result.threshold_retry->fixed;
        }
        const auto disagreeing =
            std::find_if(result.markers.begin(), result.markers.end(),
                         [](const MarkerResult& m) { return m.size_disagrees; });
        if (disagreeing != result.markers.end()) {
          if (counts.size_disagrees++ == 0)
            counts.size_disagrees_first =
                disagreeing->detection.family + "/" + std::to_string(disagreeing->detection.id);
        }
        if (!result.markers.empty()) ++counts.with_markers;
        if (result.pose) {
          ++counts.with_pose;
          tum.write(tum_line(frame.stamp_s, result.pose->T_world_lidar));
        }
      }
      line["frame"] = frame.index;
      line["timestamp"] = frame.stamp_s;
      if (window.capacity() > 1) line["window"] = {window_first, frame.index};
      if (window.seconds() > 0) line["window_frames"] = window.size();
      jsonl.write(line.dump());
      if (html) html->add(line);
      ++counts.results;
      progress.update(counts.frames);
    }
  } catch (const InputError& e) {
    progress.finish();
    std::string done = "after " + std::to_string(counts.frames) + " frames";
    if (jsonl.active() || tum.active())
      done += "; the results before it are in " +
              (jsonl.active() ? args.jsonl_path : std::string()) +
              (jsonl.active() && tum.active() ? " and " : "") +
              (tum.active() ? args.tum_path : std::string());
    throw InputError(std::string(e.what()) + " (" + done + ")");
  }
  progress.finish();
  if (args.window_seconds > 0 && counts.results == 0)
    throw file_error(source->name(), "--window-seconds " + std::to_string(args.window_seconds) +
                                         " but the recording spans " +
                                         std::to_string(last_stamp - first_stamp) + " s");
  if (counts.frames < static_cast<std::size_t>(args.frames))
    throw file_error(source->name(), "--frames " + std::to_string(args.frames) +
                                         " but the recording holds " +
                                         std::to_string(counts.frames) + " frames");
  if (html) {
    if (args.html_frame >= 0 && !html->showing()) {
      const std::string frame = "--html-frame " + std::to_string(args.html_frame) + ": ";
      if (static_cast<std::size_t>(args.html_frame) >= counts.frames)
        throw file_error(source->name(), frame + "the recording has frames 0 to " +
                                             std::to_string(counts.frames - 1));
      throw file_error(source->name(), frame + "that frame has no result (no valid points, or " +
                                           "before the first full --frames window)");
    }
    html->write(args.html_path);
  }
  if (!args.quiet) {
    // Streamed, not through a fixed buffer: a long recording path is not cut.
    std::ostream& out = report_stream(is_stdout(args.jsonl_path) || is_stdout(args.tum_path));
    out << counts.frames << (counts.frames == 1 ? " frame from " : " frames from ")
        << source->name() << ": " << counts.results << " result(s), markers in "
        << counts.with_markers << ", LiDAR pose in " << counts.with_pose << "; " << std::fixed
        << std::setprecision(1) << progress.rate(counts.frames) << " frames/s" << std::endl;
    out << std::defaultfloat << std::setprecision(6);
    if (counts.threshold_replaced > 0)
      out << "note: in " << counts.threshold_replaced << " result(s) the threshold "
          << counts.threshold
          << " lay above every intensity: the cloud's intensity is not on the sensor preset's "
             "scale, so Otsu's threshold was used there (image.threshold_replaced; give "
             "--threshold to choose one)"
          << std::endl;
    if (counts.found_at_otsu > 0)
      out << "note: in " << counts.found_at_otsu << " result(s) the sensor preset's threshold "
          << counts.threshold
          << " found no marker and Otsu's threshold found some: the print's intensity is not "
             "where the preset expects it (image.threshold_retry; give --threshold to choose one)"
          << std::endl;
    if (counts.size_disagrees > 0)
      out << "note: in " << counts.size_disagrees << " result(s) a marker (first "
          << counts.size_disagrees_first
          << ") measured another size than the map or --marker-size gives (size_disagrees, "
             "measured_size_m): the size is the black square's edge, without the white margin"
          << std::endl;
    if (counts.no_intensity > 0)
      out << "warning: in " << counts.no_intensity
          << " result(s) every point's intensity was 0: the cloud carries none (no intensity, "
             "reflectivity or i field?), and markers are seen in the intensity"
          << std::endl;
    if (counts.threshold_above_all > 0)
      out << "warning: in " << counts.threshold_above_all << " result(s) the threshold "
          << counts.threshold
          << " lay above every intensity, so no pixel was white; try --threshold otsu" << std::endl;
  }
  return 0;
}

}  // namespace iilfm::cli
