// Hostile input through the `iilfm` program: an image over --max-image-pixels, contradictory and
// warped marker maps, degenerate clouds. Refusals exit 2 with one line on stderr naming the file
// and the problem, print nothing on stdout and leave no JSON behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli_run.hpp"

namespace {

namespace fs = std::filesystem;

using iilfm::testing::cli_temp_dir;
using iilfm::testing::CliRun;
using iilfm::testing::run_cli;

// A Mid-40 scan of the tag wall, made once.
const std::string& tag_wall_scan() {
  static const std::string path = [] {
    const std::string p = (cli_temp_dir() / "hostile_tag_wall.pcd").string();
    if (run_cli("sim --scene tag-wall --frames 5 --out " + p).status != 0)
      throw std::runtime_error("iilfm sim failed");
    return p;
  }();
  return path;
}

// Exit 2, one line on stderr holding every needle, nothing on stdout, no JSON file.
void expect_refused(const std::string& args, const fs::path& json,
                    const std::vector<std::string>& needles) {
  fs::remove(json);
  const CliRun r = run_cli(args + " --json " + json.string());
  EXPECT_EQ(r.status, 2) << args << "\n" << r.err;
  ASSERT_FALSE(r.err.empty()) << args;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line expected: " << r.err;
  for (const std::string& needle : needles)
    EXPECT_NE(r.err.find(needle), std::string::npos) << "'" << needle << "' missing: " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_FALSE(fs::exists(json)) << "JSON written for a refused run: " << args;
}

void write_map(const fs::path& path, const std::string& markers) {
  std::ofstream(path) << "markers:\n" << markers;
}

TEST(CliHostile, ImageOverTheLimitIsRefusedWithAHint) {
  const fs::path json = cli_temp_dir() / "over_limit.json";
  // The Mid-40 preset's 0.05 deg pixels give an image of about 770 x 770.
  expect_refused("detect " + tag_wall_scan() + " --sensor mid40 --max-image-pixels 100000", json,
                 {tag_wall_scan(), "over the limit of 100000", "--res-h", "--max-image-pixels"});
  // A resolution typo (0.0001 deg) without a preset hits the default limit.
  expect_refused("detect " + tag_wall_scan() + " --res-h 0.0001 --res-v 0.0001", json,
                 {tag_wall_scan(), "over the limit of 50000000"});
  // The same scan under the limit runs.
  const CliRun ok = run_cli("detect " + tag_wall_scan() +
                            " --sensor mid40 --max-image-pixels 1000000 --json " + json.string());
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_TRUE(fs::exists(json));
  EXPECT_EQ(run_cli("detect " + tag_wall_scan() + " --max-image-pixels 0").status, 2);
}

TEST(CliHostile, SequenceFrameOverTheLimitNamesTheFrame) {
  const fs::path folder = cli_temp_dir() / "over_limit_sequence";
  fs::create_directories(folder);
  fs::copy_file(tag_wall_scan(), folder / "000.pcd", fs::copy_options::overwrite_existing);
  const fs::path jsonl = cli_temp_dir() / "over_limit.jsonl";
  const CliRun r = run_cli("detect " + folder.string() + " --sensor mid40 --max-image-pixels 1000" +
                           " -q --jsonl " + jsonl.string());
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line expected: " << r.err;
  EXPECT_NE(r.err.find((folder / "000.pcd").string() + ": intensity image would be"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("after 1 frames"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(CliHostile, ContradictoryOrWarpedMapsAreRefusedNamingTheMarker) {
  const fs::path d = cli_temp_dir();
  const fs::path json = d / "bad_map.json";
  const std::string square =
      "corners: [[3.62,0.086,0.571],[3.62,-0.086,0.571],[3.62,-0.086,0.399],[3.62,0.086,0.399]]";
  // The same marker twice, at two places: which one is right cannot be known.
  const fs::path duplicate = d / "duplicate.yaml";
  write_map(duplicate, "  - {family: apriltag:tag36h11, id: 0, " + square +
                           "}\n  - {family: apriltag:tag36h11, id: 0, size: 0.172, pose: "
                           "{position: [3.62, 1, 0.485], rpy_deg: [90, 0, -90]}}\n");
  expect_refused("detect " + tag_wall_scan() + " --sensor mid40 --map " + duplicate.string(), json,
                 {duplicate.string(), "apriltag:tag36h11/0", "duplicate"});
  // One corner 3 cm off the plane of the other three.
  const fs::path warped = d / "warped.yaml";
  write_map(warped,
            "  - {family: apriltag:tag36h11, id: 0, corners: [[3.62,0.086,0.571],"
            "[3.62,-0.086,0.571],[3.65,-0.086,0.399],[3.62,0.086,0.399]]}\n");
  expect_refused("detect " + tag_wall_scan() + " --sensor mid40 --map " + warped.string(), json,
                 {warped.string(), "not planar"});
  // Corners far beyond any scene: their squares overflow.
  const fs::path huge = d / "huge.yaml";
  write_map(huge,
            "  - {family: apriltag:tag36h11, id: 0, corners: [[1e300,0,0],[1e300,-1e300,0],"
            "[1e300,-1e300,-1e300],[1e300,0,-1e300]]}\n");
  expect_refused("detect " + tag_wall_scan() + " --sensor mid40 --map " + huge.string(), json,
                 {huge.string()});
}

TEST(CliHostile, DegenerateCloudsGiveAnAnswerOrAOneLineRefusal) {
  const fs::path d = cli_temp_dir();
  const fs::path json = d / "degenerate.json";
  const std::string header =
      "VERSION .7\nFIELDS x y z intensity\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n";
  // One point: nothing to estimate a resolution from.
  const fs::path one = d / "one.pcd";
  std::ofstream(one) << header << "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n3 0 0.5 40\n";
  expect_refused("detect " + one.string(), json, {one.string(), "too few points"});
  // With a preset it is a valid, empty answer: no marker, no pose.
  const CliRun r = run_cli("detect " + one.string() + " --sensor vlp16 --json " + json.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(iilfm::testing::slurp(json).find("\"markers\": []"), std::string::npos);
}

}  // namespace
