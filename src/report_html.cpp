#include "iilfm/report_html.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "iilfm/error.hpp"
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

// Every k-th point, at most `max_points`: positions as float32 x y z, intensity scaled like the
// intensity image's gray (so colours match the picture) as uint8.
json cloud_json(const PointView& points, double intensity_scale, std::size_t max_points) {
  const std::size_t n = points.size();
  const std::size_t step =
      std::max<std::size_t>(1, (n + max_points - 1) / std::max<std::size_t>(1, max_points));
  std::vector<float> xyz;
  std::vector<std::uint8_t> intensity;
  xyz.reserve(3 * (n / step + 1));
  intensity.reserve(n / step + 1);
  const double scale = intensity_scale > 0 ? 255.0 / intensity_scale : 1.0;
  for (std::size_t i = 0; i < n; i += step) {
    const float x = points.x[i], y = points.y[i], z = points.z[i];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) continue;
    xyz.insert(xyz.end(), {x, y, z});
    const double v = points.intensity[i] * scale;
    intensity.push_back(
        static_cast<std::uint8_t>(std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 255.0)));
  }
  return {{"total", n},
          {"shown", intensity.size()},
          {"step", step},
          {"xyz_f32",
           base64(reinterpret_cast<const std::uint8_t*>(xyz.data()), xyz.size() * sizeof(float))},
          {"intensity_u8", base64(intensity.data(), intensity.size())}};
}

json frame_json(const HtmlFrame& frame, const HtmlReportOptions& options) {
  const FrameResult& result = *frame.result;
  json out = result_to_json(result, frame.input);
  out["cloud"] = cloud_json(frame.points, result.preprocessed.intensity_scale, options.max_points);
  // JPEG: the noisy gray picture is ~8x smaller than as PNG, and the drawn lines stay sharp
  // enough at this quality.
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", draw_overlay(result), jpeg, {cv::IMWRITE_JPEG_QUALITY, 90});
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
#view { position: relative; height: 560px; background: #10141c; border-radius: 6px;
        overflow: hidden; }
#view canvas { display: block; }
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

std::string html_report(const std::vector<HtmlFrame>& frames, const HtmlReportOptions& options) {
  if (!html_report_available())
    throw InputError(
        "--html: this iilfm was built without the HTML report (configured with "
        "-DIILFM_HTML_REPORT=OFF)");
  if (frames.empty()) throw InputError("--html: no frame to report");
  json data = {{"title", options.title}, {"max_points", options.max_points}};
  data["frames"] = json::array();
  for (const HtmlFrame& frame : frames) data["frames"].push_back(frame_json(frame, options));

  std::string page;
  page += "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  page += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  page += "<title>" + escaped(options.title) + "</title>\n<style>" + kStyle + "</style>\n";
  page += "</head>\n<body>\n<h1>" + escaped(options.title) + "</h1>\n";
  page += "<main id=\"report\"></main>\n";
  page += "<noscript>This report needs JavaScript.</noscript>\n";
  page += "<script id=\"iilfm-data\" type=\"application/json\">" + script_safe(data.dump()) +
          "</script>\n";
  page += "<script>\n";
  page += detail::report_viewer_script();
  page += "\n</script>\n</body>\n</html>\n";
  return page;
}

void write_html_report(const std::string& path, const std::vector<HtmlFrame>& frames,
                       const HtmlReportOptions& options) {
  const std::string page = html_report(frames, options);
  std::ofstream file(path, std::ios::binary);
  if (!file || !file.write(page.data(), static_cast<std::streamsize>(page.size())) || !file.flush())
    throw file_error(path, "cannot write HTML report");
}

}  // namespace iilfm
