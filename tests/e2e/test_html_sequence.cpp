// `iilfm detect FOLDER --jsonl ... --html ...`: the report of a recording holds one summary per
// JSON line and the frame chosen by --html-frame (default: the last with markers); misuse of
// --html-frame is refused with status 2. The page itself is checked in Chromium by the ctest
// html_sequence_report_browser (web/test).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"

namespace {

namespace fs = std::filesystem;
using iilfm::testing::cli_temp_dir;
using iilfm::testing::CliRun;
using iilfm::testing::run_cli;
using iilfm::testing::slurp;
using nlohmann::json;

json page_data(const std::string& page) {
  const std::string open = "<script id=\"iilfm-data\" type=\"application/json\">";
  const std::size_t begin = page.find(open);
  if (begin == std::string::npos) return nullptr;
  std::string text = page.substr(begin + open.size());
  text = text.substr(0, text.find("</script>"));
  for (std::size_t at = text.find("<\\/"); at != std::string::npos; at = text.find("<\\/", at))
    text.replace(at, 3, "</");
  return json::parse(text);
}

// Three ULTRA Puck scans of the tag grid from a moving LiDAR; the middle one looks at the floor
// (pitched down 60 degrees), so it has no marker.
const fs::path& recording() {
  static const fs::path dir = [] {
    const fs::path d = cli_temp_dir() / "html_sequence";
    fs::create_directories(d / "scans");
    const char* poses[] = {"--lidar-xyz 0.1 -0.2 0.6 --lidar-rpy 0 0 -4",
                           "--lidar-xyz 0.2 -0.1 0.6 --lidar-rpy 0 60 0",
                           "--lidar-xyz 0.3 0.0 0.62 --lidar-rpy 0 0 3"};
    for (int k = 0; k < 3; ++k) {
      const CliRun sim = run_cli("sim --scene grid --sensor ultrapuck --seed " +
                                 std::to_string(k + 1) + " " + poses[k] + " --out " +
                                 (d / "scans" / ("s" + std::to_string(k) + ".pcd")).string() +
                                 " --map " + (d / "map.yaml").string());
      if (sim.status != 0) throw std::runtime_error("sim failed: " + sim.err);
    }
    return d;
  }();
  return dir;
}

std::vector<json> read_jsonl(const fs::path& path) {
  std::vector<json> lines;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) lines.push_back(json::parse(line));
  return lines;
}

TEST(HtmlSequence, FolderReportMatchesTheJsonLines) {
  const fs::path& d = recording();
  const fs::path jsonl = d / "run.jsonl", html = d / "run.html";
  const std::string common = "detect " + (d / "scans").string() + " --sensor ultrapuck --map " +
                             (d / "map.yaml").string() + " --jsonl " + jsonl.string() + " --html " +
                             html.string() + " -q";
  const CliRun r = run_cli(common);
  ASSERT_EQ(r.status, 0) << r.err;
  const std::vector<json> lines = read_jsonl(jsonl);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_FALSE(lines[0]["markers"].empty());
  EXPECT_TRUE(lines[1]["markers"].empty());
  EXPECT_FALSE(lines[2]["markers"].empty());

  const json data = page_data(slurp(html));
  ASSERT_FALSE(data.is_null());
  const json& frames = data["sequence"]["frames"];
  ASSERT_EQ(frames.size(), lines.size());
  for (std::size_t k = 0; k < lines.size(); ++k) {
    EXPECT_EQ(frames[k]["frame"], lines[k]["frame"]);
    EXPECT_EQ(frames[k]["markers"].size(), lines[k]["markers"].size());
    EXPECT_EQ(frames[k].contains("xyz"), !lines[k]["pose"].is_null());
  }
  EXPECT_EQ(data["sequence"]["map"].size(), 35u);
  // The last frame with markers is shown in full.
  EXPECT_EQ(data["sequence"]["shown"], 2);
  ASSERT_EQ(data["frames"].size(), 1u);
  EXPECT_EQ(data["frames"][0]["markers"].size(), lines[2]["markers"].size());

  const CliRun first = run_cli(common + " --html-frame 0");
  ASSERT_EQ(first.status, 0) << first.err;
  const json chosen = page_data(slurp(html));
  EXPECT_EQ(chosen["sequence"]["shown"], 0);
  EXPECT_EQ(chosen["frames"][0]["input"]["path"], lines[0]["input"]["path"]);
}

TEST(HtmlSequence, HtmlFrameMisuseIsRefused) {
  const fs::path& d = recording();
  const std::string scans = (d / "scans").string();
  const fs::path html = d / "refused.html";
  const CliRun beyond =
      run_cli("detect " + scans + " --sensor ultrapuck --jsonl " + (d / "x.jsonl").string() +
              " --html " + html.string() + " --html-frame 3 -q");
  EXPECT_EQ(beyond.status, 2);
  EXPECT_EQ(beyond.err, "iilfm: " + scans + ": --html-frame 3: the recording has frames 0 to 2\n");
  EXPECT_FALSE(fs::exists(html));
  const CliRun window =
      run_cli("detect " + scans + " --sensor ultrapuck --frames 2 --tum " + (d / "x.txt").string() +
              " --html " + html.string() + " --html-frame 0 -q");
  EXPECT_EQ(window.status, 2);
  EXPECT_NE(window.err.find("--html-frame 0: that frame has no result"), std::string::npos)
      << window.err;
  const CliRun alone = run_cli("detect " + scans + " --sensor ultrapuck --html-frame 1");
  EXPECT_EQ(alone.status, 2);
  EXPECT_EQ(alone.err,
            "iilfm: --html-frame selects the frame the --html report of a sequence shows\n");
  const CliRun single = run_cli("detect " + (d / "scans" / "s0.pcd").string() +
                                " --sensor ultrapuck --html " + html.string() + " --html-frame 0");
  EXPECT_EQ(single.status, 2);
  EXPECT_NE(single.err.find("--html-frame is for sequences"), std::string::npos) << single.err;
}

}  // namespace
