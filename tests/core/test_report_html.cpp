// The HTML report page: self-contained, the frame's JSON result inside, points subsampled to the
// cap, nothing from names leaking into the markup.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "iilfm/error.hpp"
#include "iilfm/io/cloud_io.hpp"
#include "iilfm/marker_map.hpp"
#include "iilfm/report_html.hpp"
#include "iilfm/sensor.hpp"

namespace iilfm {
namespace {

// The data element of a page, parsed.
nlohmann::json page_data(const std::string& page) {
  const std::string open = "<script id=\"iilfm-data\" type=\"application/json\">";
  const std::size_t begin = page.find(open) + open.size();
  std::string text = page.substr(begin, page.find("</script>", begin) - begin);
  for (std::size_t at = text.find("<\\/"); at != std::string::npos; at = text.find("<\\/", at))
    text.replace(at, 3, "</");
  return nlohmann::json::parse(text);
}

TEST(HtmlReport, HoldsTheFrameResultAndSubsampledPoints) {
  ASSERT_TRUE(html_report_available());
  const std::string dir = IILFM_SOURCE_DIR "/data/sample/";
  const io::LoadedCloud loaded = io::read_cloud(dir + "mid40_tag_wall.pcd");
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("mid40"), options);
  options.map = MarkerMap::load(dir + "mid40_tag_wall_map.yaml");
  Pipeline pipeline(options);
  const FrameResult& result = pipeline.process(loaded.cloud);
  const InputInfo info{"</script><b>scan.pcd", loaded.stats, 1.5, "preset mid40"};

  HtmlReportOptions report;
  report.title = "a <title> & more";
  report.max_points = 30'000;
  const std::string page = html_report({HtmlFrame{&result, info, PointView(loaded.cloud)}}, report);

  EXPECT_EQ(page.rfind("<!doctype html>", 0), 0u);
  EXPECT_NE(page.find("<title>a &lt;title&gt; &amp; more</title>"), std::string::npos);
  // The name cannot close the data element: "</" is escaped inside it.
  EXPECT_EQ(page.find("</script><b>"), std::string::npos);
  EXPECT_NE(page.find("<\\/script><b>scan.pcd"), std::string::npos);
  EXPECT_EQ(page.find("src=\"http"), std::string::npos);  // nothing fetched
  EXPECT_NE(page.find("Three.js Authors"), std::string::npos);

  const nlohmann::json data = page_data(page);
  ASSERT_EQ(data["frames"].size(), 1u);
  const nlohmann::json& frame = data["frames"][0];
  EXPECT_EQ(frame["input"]["path"], info.path);
  nlohmann::json expected = result_to_json(result, info);
  EXPECT_EQ(frame["markers"], expected["markers"]);
  EXPECT_EQ(frame["pose"], expected["pose"]);
  const std::size_t n = loaded.cloud.size();
  const std::size_t step = (n + 29'999) / 30'000;
  EXPECT_EQ(frame["cloud"]["total"], n);
  EXPECT_EQ(frame["cloud"]["step"], step);
  EXPECT_EQ(frame["cloud"]["shown"], (n + step - 1) / step);
  EXPECT_LE(frame["cloud"]["shown"].get<std::size_t>(), 30'000u);
  // base64 of shown * 3 float32 positions and shown intensity bytes.
  const std::size_t shown = frame["cloud"]["shown"];
  EXPECT_EQ(frame["cloud"]["xyz_f32"].get<std::string>().size(), (shown * 12 + 2) / 3 * 4);
  EXPECT_EQ(frame["cloud"]["intensity_u8"].get<std::string>().size(), (shown + 2) / 3 * 4);
  EXPECT_EQ(frame["overlay_image"].get<std::string>().rfind("data:image/jpeg;base64,", 0), 0u);
}

TEST(HtmlReport, RefusesNoFramesAndUnwritablePaths) {
  EXPECT_THROW(html_report({}), InputError);
  FrameResult empty;
  PointCloud none;
  try {
    write_html_report("/nonexistent-dir/report.html",
                      {HtmlFrame{&empty, InputInfo{"x.pcd", {}, 0, ""}, PointView(none)}});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent-dir/report.html: cannot write HTML report");
  }
}

// A recording's page: one summary per frame (ids, pose, timing), the map, and the frame shown in
// full as it was when shown, although the pipeline's buffers were reused by later frames.
TEST(HtmlSequenceReport, SummarisesEveryFrameAndKeepsTheShownOne) {
  ASSERT_TRUE(html_report_available());
  const std::string dir = IILFM_SOURCE_DIR "/data/sample/";
  const io::LoadedCloud loaded = io::read_cloud(dir + "mid40_tag_wall.pcd");
  PipelineOptions options;
  apply_sensor_preset(find_sensor_preset("mid40"), options);
  options.map = MarkerMap::load(dir + "mid40_tag_wall_map.yaml");
  Pipeline pipeline(options);
  // Frame 1 is the scan without its first half of points: fewer points, markers maybe lost.
  PointCloud half = loaded.cloud;
  const std::size_t cut = half.size() / 2;
  for (auto* column : {&half.x, &half.y, &half.z, &half.intensity})
    column->erase(column->begin(), column->begin() + static_cast<std::ptrdiff_t>(cut));

  HtmlSequenceReport report;
  report.set_map(*options.map);
  std::vector<nlohmann::json> lines;
  nlohmann::json shown_markers;
  for (int k = 0; k < 3; ++k) {
    const PointCloud& cloud = k == 1 ? half : loaded.cloud;
    const InputInfo info{"rec#" + std::to_string(k), loaded.stats, 0.5, ""};
    const FrameResult& result = pipeline.process(cloud);
    nlohmann::json line = result_to_json(result, info);
    line["frame"] = 10 + k;
    line["timestamp"] = 100.0 + 0.1 * k;
    report.add(line);
    if (k == 0) {
      report.show(HtmlFrame{&result, info, PointView(cloud)}, 0);
      shown_markers = line["markers"];
    }
    lines.push_back(line);
  }
  ASSERT_EQ(report.frames(), 3u);
  const nlohmann::json data = page_data(report.page());
  const nlohmann::json& seq = data["sequence"];
  ASSERT_EQ(seq["frames"].size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const nlohmann::json& s = seq["frames"][k];
    EXPECT_EQ(s["frame"], 10 + k);
    EXPECT_DOUBLE_EQ(s["time"].get<double>(), 100.0 + 0.1 * k);
    ASSERT_EQ(s["markers"].size(), lines[k]["markers"].size());
    for (std::size_t m = 0; m < s["markers"].size(); ++m)
      EXPECT_EQ(seq["keys"][s["markers"][m].get<std::size_t>()].get<std::string>(),
                lines[k]["markers"][m]["family"].get<std::string>() + "/" +
                    std::to_string(lines[k]["markers"][m]["id"].get<int>()));
    const nlohmann::json& pose = lines[k]["pose"];
    ASSERT_EQ(s.contains("xyz"), !pose.is_null());
    if (pose.is_null()) {
      EXPECT_EQ(s["why"], lines[k]["pose_missing_reason"]);
      continue;
    }
    // Rounded to 4, 3 and 2 decimals: within half the last digit kept, a tie included (0.775 mm
    // shows as 0.78, 0.00500000000000000044 away in doubles).
    constexpr double kTie = 1e-12;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(s["xyz"][i].get<double>(), pose["xyz"][i].get<double>(), 0.5e-4 + kTie);
      EXPECT_NEAR(s["rpy"][i].get<double>(), pose["rpy_deg"][i].get<double>(), 0.5e-3 + kTie);
    }
    EXPECT_NEAR(s["rms_mm"].get<double>(), 1000 * pose["rms_m"].get<double>(), 0.005 + kTie);
    EXPECT_EQ(s["used"], pose["markers_used"].size());
  }
  EXPECT_FALSE(seq["frames"][0]["markers"].empty());
  EXPECT_EQ(seq["map"].size(), options.map->markers().size());
  EXPECT_EQ(seq["map"][0]["key"], options.map->markers()[0].key());
  // The shown frame is frame 0 as it was: its markers and its whole cloud, not the half of frame 1.
  EXPECT_EQ(seq["shown"], 0);
  ASSERT_EQ(data["frames"].size(), 1u);
  EXPECT_EQ(data["frames"][0]["markers"], shown_markers);
  EXPECT_EQ(data["frames"][0]["input"]["path"], "rec#0");
  EXPECT_EQ(data["frames"][0]["cloud"]["total"], loaded.cloud.size());
}

TEST(HtmlSequenceReport, RefusesAnEmptyRecordingAndShowsNothingUnasked) {
  HtmlSequenceReport report;
  EXPECT_THROW(report.page(), InputError);
  report.add({{"frame", 0},
              {"timestamp", 1.0},
              {"markers", nlohmann::json::array()},
              {"pose", nullptr},
              {"pose_missing_reason", "no valid points"},
              {"timing_ms", {{"total", 0.25}}}});
  EXPECT_FALSE(report.showing());
  const nlohmann::json data = page_data(report.page());
  EXPECT_TRUE(data["frames"].empty());
  EXPECT_TRUE(data["sequence"]["shown"].is_null());
  EXPECT_EQ(data["sequence"]["frames"][0]["why"], "no valid points");
}

}  // namespace
}  // namespace iilfm
