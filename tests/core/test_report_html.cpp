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

}  // namespace
}  // namespace iilfm
