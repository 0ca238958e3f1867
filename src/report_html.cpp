#include "iilfm/report_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <utility>

#include "iilfm/error.hpp"
#include "iilfm/image_files.hpp"
#include "report_viewer.hpp"

namespace iilfm {

namespace {

using nlohmann::json;

std::string base64(const std::uint8_t* data, std::size_t size) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const std::uint32_t b0 = data[i], b1 = i + 1 < size ? data[i + 1] : 0,
                        b2 = i + 2 < size ? data[i + 2] : 0;
    const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < size ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

}  // namespace

// One frame's page data, copied out of the result's reused buffers but not yet encoded (base64
// and JPEG cost more than the copies; a sequence replaces its shown frame often).
struct HtmlFrameData {
  json result;
  std::size_t total = 0, step = 1;
  std::vector<float> xyz;
  std::vector<std::uint8_t> intensity;
  cv::Mat overlay;
};

namespace {

// Every k-th point, at most `max_points`: positions as float32 x y z, intensity scaled like the
// intensity image's gray (so colours match the picture) as uint8.
void subsample(const PointView& points, double intensity_scale, std::size_t max_points,
               HtmlFrameData& out) {
  const std::size_t n = points.size();
  out.total = n;
  out.step = std::max<std::size_t>(1, (n + max_points - 1) / std::max<std::size_t>(1, max_points));
  out.xyz.reserve(3 * (n / out.step + 1));
  out.intensity.reserve(n / out.step + 1);
  const double scale = intensity_scale > 0 ? 255.0 / intensity_scale : 1.0;
  for (std::size_t i = 0; i < n; i += out.step) {
    const float x = points.x[i], y = points.y[i], z = points.z[i];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) continue;
    out.xyz.insert(out.xyz.end(), {x, y, z});
    const double v = points.intensity[i] * scale;
    out.intensity.push_back(
        static_cast<std::uint8_t>(std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 255.0)));
  }
}

HtmlFrameData frame_data(const HtmlFrame& frame, const HtmlReportOptions& options) {
  const FrameResult& result = *frame.result;
  HtmlFrameData out;
  out.result = result_to_json(result, frame.input);
  subsample(frame.points, result.preprocessed.intensity_scale, options.max_points, out);
  out.overlay = draw_overlay(result);
  return out;
}

json frame_json(const HtmlFrameData& frame) {
  json out = frame.result;
  out["cloud"] = {{"total", frame.total},
                  {"shown", frame.intensity.size()},
                  {"step", frame.step},
                  {"xyz_f32", base64(reinterpret_cast<const std::uint8_t*>(frame.xyz.data()),
                                     frame.xyz.size() * sizeof(float))},
                  {"intensity_u8", base64(frame.intensity.data(), frame.intensity.size())}};
  // JPEG: the noisy gray picture is ~8x smaller than as PNG, and the drawn lines stay sharp
  // enough at this quality.
  const std::vector<std::uint8_t> jpeg = encode_jpeg(frame.overlay, 90);
  out["overlay_image"] = "data:image/jpeg;base64," + base64(jpeg.data(), jpeg.size());
  return out;
}

// Text safe inside an HTML element: no markup from file names or titles.
std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// JSON inside <script>: "</" would end the element early.
std::string script_safe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

constexpr const char* kStyle = R"css(
body { font: 14px/1.4 system-ui, sans-serif; margin: 0 auto; max-width: 1200px; padding: 0 16px;
       color: #1d2330; background: #f6f7f9; }
h1 { font-size: 22px; margin: 16px 0 4px; } h2 { font-size: 17px; margin: 20px 0 6px; }
.view { position: relative; height: 560px; background: #10141c; border-radius: 6px;
        overflow: hidden; }
.view canvas { display: block; }
#trajectory-view { height: 480px; }
.map-label { color: #c8cede; font-size: 11px; }
#plots { display: flex; flex-wrap: wrap; gap: 8px; margin-top: 8px; }
.plot { background: #fff; border: 1px solid #d5d9e0; border-radius: 4px; }
.plot-area { fill: #fbfbfd; stroke: #d5d9e0; }
.plot-text { font: 11px system-ui, sans-serif; fill: #4a5263; }
.plot-cursor { stroke: #1d2330; stroke-dasharray: 3 2; }
.slider-row input { width: 100%; }
.frames-scroll { max-height: 320px; overflow-y: auto; margin-top: 8px; }
#frames { width: 100%; }
#frames tbody tr { cursor: pointer; }
#frames tbody tr.selected, #frame-selected td { background: #fff3c4; }
.labels { position: absolute; top: 0; left: 0; }
.label { color: #fff; font: bold 13px system-ui, sans-serif; text-shadow: 0 0 3px #000; }
.marker-label { color: #ffb040; }
.no-webgl { color: #fff; padding: 20px; }
table { border-collapse: collapse; background: #fff; }
th, td { border: 1px solid #d5d9e0; padding: 3px 8px; text-align: right; }
th { background: #e9ecf1; }
#overlay { max-width: 100%; max-height: 90vh; border-radius: 4px; }
.info { color: #4a5263; }
)css";

}  // namespace

bool html_report_available() { return !detail::report_viewer_script().empty(); }

namespace {

void require_viewer() {
  if (!html_report_available())
    throw InputError(
        "--html: this iilfm was built without the HTML report (configured with "
        "-DIILFM_HTML_REPORT=OFF)");
}

std::string page_with(const json& data, const std::string& title) {
  std::string page;
  page += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  page += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  page += "<title>" + escaped(title) + "</title>\n<style>" + kStyle + "</style>\n";
  page += "</head>\n<body>\n<h1>" + escaped(title) + "</h1>\n";
  page += "<main id=\"report\"></main>\n";
  page += "<noscript>This report needs JavaScript.</noscript>\n";
  page += "<script id=\"iilfm-data\" type=\"application/json\">" + script_safe(data.dump()) +
          "</script>\n";
  page += "<script>\n";
  page += detail::report_viewer_script();
  page += "\n</script>\n</body>\n</html>\n";
  return page;
}

void write_page(const std::string& path, const std::string& page) {
  std::ofstream file(path, std::ios::binary);
  if (!file || !file.write(page.data(), static_cast<std::streamsize>(page.size())) || !file.flush())
    throw file_error(path, "cannot write HTML report");
}

// Fewer digits than the JSON lines: the page shows millimetres and hundredths of a degree.
// Dividing by a power of ten gives the double nearest the decimal, which prints short.
double rounded(double v, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(v * scale) / scale;
}

json rounded_all(const json& values, int decimals) {
  json out = json::array();
  for (const json& v : values) out.push_back(rounded(v.get<double>(), decimals));
  return out;
}

}  // namespace

std::string html_report(const std::vector<HtmlFrame>& frames, const HtmlReportOptions& options) {
  require_viewer();
  if (frames.empty()) throw InputError("--html: no frame to report");
  json data = {{"title", options.title}, {"max_points", options.max_points}};
  data["frames"] = json::array();
  for (const HtmlFrame& frame : frames)
    data["frames"].push_back(frame_json(frame_data(frame, options)));
  return page_with(data, options.title);
}

void write_html_report(const std::string& path, const std::vector<HtmlFrame>& frames,
                       const HtmlReportOptions& options) {
  write_page(path, html_report(frames, options));
}

HtmlSequenceReport::HtmlSequenceReport(HtmlReportOptions options) : options_(std::move(options)) {}

void HtmlSequenceReport::set_map(const MarkerMap& map) {
  map_markers_ = json::array();
  for (const MapMarker& m : map.markers()) {
    json corners = json::array();
    for (const Vec3& c : m.corners_world) corners.push_back({c.x(), c.y(), c.z()});
    map_markers_.push_back({{"key", m.key()}, {"id", m.id}, {"corners_world", corners}});
  }
}

void HtmlSequenceReport::add(const json& line) {
  json markers = json::array();
  for (const json& m : line.at("markers")) {
    const std::string key =
        m.at("family").get<std::string>() + "/" + std::to_string(m.at("id").get<int>());
    auto [at, added] = key_index_.emplace(key, keys_.size());
    if (added) keys_.push_back(key);
    markers.push_back(at->second);
  }
  json summary = {{"frame", line.at("frame")},
                  {"time", line.at("timestamp")},
                  {"markers", markers},
                  {"ms", rounded(line.at("timing_ms").at("total").get<double>(), 2)}};
  const json& pose = line.at("pose");
  if (pose.is_null()) {
    summary["why"] = line.value("pose_missing_reason", "");
  } else {
    summary["xyz"] = rounded_all(pose.at("xyz"), 4);
    summary["rpy"] = rounded_all(pose.at("rpy_deg"), 3);
    summary["rms_mm"] = rounded(1000 * pose.at("rms_m").get<double>(), 2);
    summary["used"] = pose.at("markers_used").size();
  }
  if (line.contains("window")) summary["window"] = line["window"];
  summaries_.push_back(std::move(summary));
}

void HtmlSequenceReport::show(const HtmlFrame& frame, std::size_t line_index) {
  require_viewer();
  shown_ = std::make_shared<const HtmlFrameData>(frame_data(frame, options_));
  shown_index_ = line_index;
}

std::string HtmlSequenceReport::page() const {
  require_viewer();
  if (summaries_.empty()) throw InputError("--html: no frame to report");
  json data = {{"title", options_.title}, {"max_points", options_.max_points}};
  data["frames"] = json::array();
  if (shown_) data["frames"].push_back(frame_json(*shown_));
  data["sequence"] = {{"frames", summaries_},
                      {"keys", keys_},
                      {"map", map_markers_},
                      {"shown", shown_ ? json(shown_index_) : json()}};
  return page_with(data, options_.title);
}

void HtmlSequenceReport::write(const std::string& path) const { write_page(path, page()); }

}  // namespace iilfm
