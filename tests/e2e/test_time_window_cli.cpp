// `iilfm detect FOLDER --window-seconds S --jsonl ...`: the time window over frames stamped by
// their file names, its refusals, and the per-marker coverage in every line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "cli_run.hpp"

namespace {

namespace fs = std::filesystem;
using iilfm::testing::cli_temp_dir;
using iilfm::testing::run_cli;

std::vector<nlohmann::json> read_jsonl(const fs::path& path) {
  std::vector<nlohmann::json> lines;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

TEST(TimeWindowCli, IntegratesTheFramesOfTheLastSecondsAndReportsCoverage) {
  const fs::path dir = cli_temp_dir() / "time_window";
  fs::create_directories(dir);
  // Five Mid-40 scans 0.1 s apart (stamps in the file names), 20 frames each so every window
  // finds the tag.
  const char* names[] = {"100.0.pcd", "100.1.pcd", "100.2.pcd", "100.3.pcd", "100.4.pcd"};
  for (int i = 0; i < 5; ++i)
    ASSERT_EQ(run_cli("sim --scene tag-wall --frames 20 --seed " + std::to_string(i + 1) +
                      " --out " + (dir / names[i]).string())
                  .status,
              0);
  const fs::path jsonl = cli_temp_dir() / "time_window.jsonl";
  const auto run = run_cli("detect " + dir.string() +
                           " --sensor mid40 --window-seconds 0.3 -q --jsonl " + jsonl.string());
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<nlohmann::json> lines = read_jsonl(jsonl);
  // Full once the frames span 0.3 s (three frames); then one line per frame.
  ASSERT_EQ(lines.size(), 3u);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    EXPECT_EQ(lines[k]["frame"], k + 2);
    EXPECT_EQ(lines[k]["window_frames"], 3);
    EXPECT_EQ(lines[k]["window"][0], k);
    EXPECT_EQ(lines[k]["window"][1], k + 2);
    ASSERT_EQ(lines[k]["markers"].size(), 1u);
    const double coverage = lines[k]["markers"][0]["coverage"];
    EXPECT_GT(coverage, 0.3);
    EXPECT_LE(coverage, 1.0);
  }

  auto refused =
      run_cli("detect " + dir.string() +
              " --sensor mid40 --window-seconds 0.3 --frames 2 --jsonl " + jsonl.string());
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("alternatives"), std::string::npos) << refused.err;
  refused = run_cli("detect " + (dir / names[0]).string() + " --sensor mid40 --window-seconds 0.3");
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("sequences"), std::string::npos) << refused.err;
  refused = run_cli("detect " + dir.string() + " --sensor mid40 --window-seconds 5 -q --jsonl " +
                    jsonl.string());
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("spans 0.4"), std::string::npos) << refused.err;
}

}  // namespace
